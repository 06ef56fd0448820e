// The LASzip range decoder and its adaptive models (Said's fast arithmetic coder:
// 32-bit interval, periodic model updates, table lookup for large alphabets). Every
// constant and update rule below is part of the LAZ format: a decoder that rounds or
// updates differently reads a different point. Reads never leave their byte span:
// past its end the decoder sees zeros and remembers it, so a truncated or corrupt
// stream ends in an error, not a crash, and no loop depends on the data to stop.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pcl_vts {
namespace laz {

constexpr std::uint32_t MIN_LENGTH = 0x01000000u; // renormalise below this
constexpr std::uint32_t MAX_LENGTH = 0xFFFFFFFFu;
constexpr std::uint32_t BIT_LENGTH_SHIFT = 13; // bit model: 13-bit probabilities
constexpr std::uint32_t BIT_MAX_COUNT = 1u << BIT_LENGTH_SHIFT;
constexpr std::uint32_t SYMBOL_LENGTH_SHIFT = 15; // symbol model: 15-bit distribution
constexpr std::uint32_t SYMBOL_MAX_COUNT = 1u << SYMBOL_LENGTH_SHIFT;

/// Adaptive model of one binary decision.
struct BitModel {
  std::uint32_t update_cycle = 4, bits_until_update = 4;
  std::uint32_t bit_0_prob = 1u << (BIT_LENGTH_SHIFT - 1);
  std::uint32_t bit_0_count = 1, bit_count = 2;

  void update()
  {
    if ((bit_count += update_cycle) > BIT_MAX_COUNT) { // halve the counts
      bit_count = (bit_count + 1) >> 1;
      bit_0_count = (bit_0_count + 1) >> 1;
      if (bit_0_count == bit_count)
        ++bit_count;
    }
    const std::uint32_t scale = 0x80000000u / bit_count;
    bit_0_prob = (bit_0_count * scale) >> (31 - BIT_LENGTH_SHIFT);
    update_cycle = (5 * update_cycle) >> 2;
    if (update_cycle > 64)
      update_cycle = 64;
    bits_until_update = update_cycle;
  }
};

/// Adaptive model of an alphabet of 2..2048 symbols; alphabets above 16 symbols
/// keep a lookup table that narrows the search before the bisection.
class SymbolModel {
 public:
  explicit SymbolModel(std::uint32_t symbols);

  void update();

  std::uint32_t symbols;
  std::uint32_t last_symbol;
  std::uint32_t table_size = 0, table_shift = 0;
  std::uint32_t total_count = 0, update_cycle, symbols_until_update;
  std::vector<std::uint32_t> distribution, symbol_count, decoder_table;
};

/// Decodes one arithmetic-coded stream held in [begin, end).
class ArithmeticDecoder {
 public:
  ArithmeticDecoder() = default;
  ArithmeticDecoder(const std::uint8_t* begin, const std::uint8_t* end)
  {
    start(begin, end);
  }

  /// Starts on a new stream: reads its first four bytes.
  void start(const std::uint8_t* begin, const std::uint8_t* end)
  {
    at_ = begin;
    end_ = end;
    overrun_ = 0;
    length_ = MAX_LENGTH;
    value_ = 0;
    for (int k = 0; k < 4; ++k)
      value_ = (value_ << 8) | nextByte();
  }

  /// Bytes of the stream not read yet.
  std::size_t unread() const { return static_cast<std::size_t>(end_ - at_); }
  /// Bytes asked for beyond the stream's end (0 for an intact stream).
  std::size_t overrun() const { return overrun_; }

  std::uint32_t decodeBit(BitModel& m)
  {
    const std::uint32_t x = m.bit_0_prob * (length_ >> BIT_LENGTH_SHIFT);
    const std::uint32_t bit = value_ >= x;
    if (bit == 0) {
      length_ = x;
      ++m.bit_0_count;
    } else {
      value_ -= x;
      length_ -= x;
    }
    if (length_ < MIN_LENGTH)
      renormalise();
    if (--m.bits_until_update == 0)
      m.update();
    return bit;
  }

  std::uint32_t decodeSymbol(SymbolModel& m);

  /// `bits` raw bits (1..32), low 16 first when more than 19.
  std::uint32_t readBits(std::uint32_t bits)
  {
    if (bits > 19) {
      const std::uint32_t low = readShort();
      return (readBits(bits - 16) << 16) | low;
    }
    return readRaw(bits);
  }
  std::uint32_t readShort() { return readRaw(16); }
  std::uint32_t readInt()
  {
    const std::uint32_t low = readShort();
    return (readShort() << 16) | low;
  }

 private:
  std::uint32_t nextByte()
  {
    if (at_ < end_)
      return *at_++;
    ++overrun_;
    return 0;
  }
  std::uint32_t readRaw(std::uint32_t bits)
  {
    const std::uint32_t sym = value_ / (length_ >>= bits);
    value_ -= length_ * sym;
    if (length_ < MIN_LENGTH)
      renormalise();
    return sym;
  }
  void renormalise()
  {
    // A corrupt stream can empty the interval; keep it non-empty so the loop ends
    // (the stream is garbage by then, and its overrun or the caller's checks say so).
    if (length_ == 0) {
      length_ = MIN_LENGTH;
      ++overrun_;
    }
    do {
      value_ = (value_ << 8) | nextByte();
    } while ((length_ <<= 8) < MIN_LENGTH);
  }

  const std::uint8_t* at_ = nullptr;
  const std::uint8_t* end_ = nullptr;
  std::size_t overrun_ = 0;
  std::uint32_t value_ = 0, length_ = MAX_LENGTH;
};

} // namespace laz
} // namespace pcl_vts
