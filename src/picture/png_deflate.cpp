// Fixed-Huffman deflate with hash-chain LZ77. See png_deflate.h.
#include "png_deflate.h"

#include <algorithm>
#include <array>

namespace pcl_vts {
namespace png_detail {

namespace {

constexpr std::size_t WINDOW = 32768;
constexpr std::size_t MIN_MATCH = 3;
constexpr std::size_t MAX_MATCH = 258;
constexpr int HASH_BITS = 15;
constexpr int MAX_CHAIN = 24; // candidates tried per position: speed over the last %
constexpr std::uint32_t NO_POSITION = 0xFFFFFFFFu;

/// Bits are packed least significant first (RFC 1951 3.1.1).
class BitWriter {
 public:
  explicit BitWriter(std::vector<std::uint8_t>& out)
      : out_(out)
  {}

  void put(std::uint32_t value, int count)
  {
    buffer_ |= static_cast<std::uint64_t>(value) << filled_;
    filled_ += count;
    while (filled_ >= 8) {
      out_.push_back(static_cast<std::uint8_t>(buffer_));
      buffer_ >>= 8;
      filled_ -= 8;
    }
  }

  void flush()
  {
    if (filled_ > 0)
      out_.push_back(static_cast<std::uint8_t>(buffer_));
    buffer_ = 0;
    filled_ = 0;
  }

 private:
  std::vector<std::uint8_t>& out_;
  std::uint64_t buffer_ = 0;
  int filled_ = 0;
};

std::uint32_t reverseBits(std::uint32_t code, int length)
{
  std::uint32_t r = 0;
  for (int i = 0; i < length; ++i)
    r |= ((code >> i) & 1u) << (length - 1 - i);
  return r;
}

/// Fixed literal/length code (RFC 1951 3.2.6), bit-reversed for the LSB-first writer.
struct FixedCodes {
  std::array<std::uint32_t, 288> code{};
  std::array<int, 288> length{};
  FixedCodes()
  {
    for (int s = 0; s < 288; ++s) {
      std::uint32_t c;
      int n;
      if (s < 144)
        c = 0x30 + s, n = 8;
      else if (s < 256)
        c = 0x190 + (s - 144), n = 9;
      else if (s < 280)
        c = s - 256, n = 7;
      else
        c = 0xC0 + (s - 280), n = 8;
      code[s] = reverseBits(c, n);
      length[s] = n;
    }
  }
};

constexpr std::array<int, 29> LENGTH_BASE = {
    3,  4,  5,  6,  7,  8,  9,  10, 11,  13,  15,  17,  19,  23, 27,
    31, 35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258};
constexpr std::array<int, 29> LENGTH_EXTRA = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1,
                                              1, 1, 2, 2, 2, 2, 3, 3, 3, 3,
                                              4, 4, 4, 4, 5, 5, 5, 5, 0};
constexpr std::array<int, 30> DISTANCE_BASE = {
    1,    2,    3,    4,    5,    7,    9,    13,    17,    25,
    33,   49,   65,   97,   129,  193,  257,  385,   513,   769,
    1025, 1537, 2049, 3073, 4097, 6145, 8193, 12289, 16385, 24577};
constexpr std::array<int, 30> DISTANCE_EXTRA = {0, 0, 0,  0,  1,  1,  2,  2,  3,  3,
                                                4, 4, 5,  5,  6,  6,  7,  7,  8,  8,
                                                9, 9, 10, 10, 11, 11, 12, 12, 13, 13};

class FixedHuffmanEncoder {
 public:
  explicit FixedHuffmanEncoder(BitWriter& bits)
      : bits_(bits)
  {}

  void literal(int symbol) { bits_.put(codes().code[symbol], codes().length[symbol]); }

  void match(int length, int distance)
  {
    const int l = static_cast<int>(
        std::upper_bound(LENGTH_BASE.begin(), LENGTH_BASE.end(), length) -
        LENGTH_BASE.begin() - 1);
    literal(257 + l);
    bits_.put(static_cast<std::uint32_t>(length - LENGTH_BASE[l]), LENGTH_EXTRA[l]);
    const int d = static_cast<int>(
        std::upper_bound(DISTANCE_BASE.begin(), DISTANCE_BASE.end(), distance) -
        DISTANCE_BASE.begin() - 1);
    bits_.put(reverseBits(static_cast<std::uint32_t>(d), 5), 5); // fixed 5-bit codes
    bits_.put(static_cast<std::uint32_t>(distance - DISTANCE_BASE[d]),
              DISTANCE_EXTRA[d]);
  }

 private:
  static const FixedCodes& codes()
  {
    static const FixedCodes table;
    return table;
  }
  BitWriter& bits_;
};

std::uint32_t hash3(const std::uint8_t* p)
{
  const std::uint32_t v =
      (std::uint32_t{p[0]} << 16) | (std::uint32_t{p[1]} << 8) | p[2];
  return (v * 2654435761u) >> (32 - HASH_BITS);
}

/// Greedy LZ77: the longest match among the last MAX_CHAIN positions with the same
/// 3-byte hash, inside the window.
void compressBlock(const std::uint8_t* data, std::size_t size, FixedHuffmanEncoder& enc)
{
  std::vector<std::uint32_t> head(std::size_t{1} << HASH_BITS, NO_POSITION);
  std::vector<std::uint32_t> prev(WINDOW, NO_POSITION);
  auto insert = [&](std::size_t pos) {
    const std::uint32_t h = hash3(data + pos);
    prev[pos % WINDOW] = head[h];
    head[h] = static_cast<std::uint32_t>(pos);
  };
  std::size_t i = 0;
  while (i < size) {
    std::size_t best_length = 0, best_distance = 0;
    if (i + MIN_MATCH <= size) {
      const std::size_t limit = std::min(MAX_MATCH, size - i);
      std::uint32_t candidate = head[hash3(data + i)];
      for (int chain = 0; chain < MAX_CHAIN && candidate != NO_POSITION; ++chain) {
        if (i - candidate > WINDOW - 1 || candidate >= i)
          break;
        const std::uint8_t* a = data + candidate;
        const std::uint8_t* b = data + i;
        if (a[best_length] == b[best_length]) { // cheap reject before the full compare
          std::size_t n = 0;
          while (n < limit && a[n] == b[n])
            ++n;
          if (n > best_length) {
            best_length = n;
            best_distance = i - candidate;
            if (n == limit)
              break;
          }
        }
        const std::uint32_t next = prev[candidate % WINDOW];
        if (next != NO_POSITION && next >= candidate)
          break; // the slot was reused by a newer position: the chain is over
        candidate = next;
      }
    }
    if (best_length >= MIN_MATCH) {
      enc.match(static_cast<int>(best_length), static_cast<int>(best_distance));
      const std::size_t end = i + best_length;
      for (; i < end; ++i)
        if (i + MIN_MATCH <= size)
          insert(i);
    } else {
      enc.literal(data[i]);
      if (i + MIN_MATCH <= size)
        insert(i);
      ++i;
    }
  }
}

} // namespace

std::uint32_t adler32(const std::uint8_t* data, std::size_t size)
{
  constexpr std::uint32_t MOD = 65521;
  constexpr std::size_t NMAX = 5552; // largest run without 32-bit overflow (zlib)
  std::uint32_t a = 1, b = 0;
  while (size > 0) {
    const std::size_t n = std::min(size, NMAX);
    for (std::size_t k = 0; k < n; ++k) {
      a += data[k];
      b += a;
    }
    a %= MOD;
    b %= MOD;
    data += n;
    size -= n;
  }
  return (b << 16) | a;
}

std::vector<std::uint8_t> zlibCompress(const std::uint8_t* data, std::size_t size)
{
  std::vector<std::uint8_t> out;
  out.reserve(size / 4 + 64);
  out.push_back(0x78); // deflate, 32 KiB window
  out.push_back(0x01); // no dictionary, fastest level; (0x7801 % 31 == 0)
  BitWriter bits(out);
  bits.put(1, 1); // final block
  bits.put(1, 2); // fixed Huffman codes
  FixedHuffmanEncoder enc(bits);
  compressBlock(data, size, enc);
  enc.literal(256); // end of block
  bits.flush();
  const std::uint32_t adler = adler32(data, size);
  for (int k = 3; k >= 0; --k)
    out.push_back(static_cast<std::uint8_t>(adler >> (8 * k)));
  return out;
}

} // namespace png_detail
} // namespace pcl_vts
