// Version 2 pointwise items (LASzip 2.x): POINT10, GPSTIME11, RGB12, BYTE. Each
// predicts the record from the previous one of its chunk; see item_decoder.h.
#include "integer_decoder.h"
#include "item_decoder.h"
#include "item_state.h"

namespace pcl_vts {
namespace laz {
namespace {

// Context of return r of n (formats 0-5). Well-formed files use the upper-left
// triangle; the rest gives context to files that number returns from 0 or swap them.
constexpr std::uint8_t NUMBER_RETURN_MAP[8][8] = {
    {15, 14, 13, 12, 11, 10, 9, 8},  {14, 0, 1, 3, 6, 10, 10, 9},
    {13, 1, 2, 4, 7, 11, 11, 10},    {12, 3, 4, 5, 8, 12, 12, 11},
    {11, 6, 7, 8, 9, 13, 13, 12},    {10, 10, 11, 12, 13, 14, 14, 13},
    {9, 10, 11, 12, 13, 14, 15, 14}, {8, 9, 10, 11, 12, 13, 14, 15}};

/// The 20 bytes of a point format 0 record.
struct Point10 {
  std::int32_t x = 0, y = 0, z = 0;
  std::uint16_t intensity = 0;
  std::uint8_t bits = 0; // return number 0-2, number of returns 3-5, scan dir, edge
  std::uint8_t classification = 0;
  std::uint8_t scan_angle = 0;
  std::uint8_t user_data = 0;
  std::uint16_t point_source = 0;

  void read(const std::uint8_t* p)
  {
    x = load<std::int32_t>(p);
    y = load<std::int32_t>(p + 4);
    z = load<std::int32_t>(p + 8);
    intensity = load<std::uint16_t>(p + 12);
    bits = p[14];
    classification = p[15];
    scan_angle = p[16];
    user_data = p[17];
    point_source = load<std::uint16_t>(p + 18);
  }
  void write(std::uint8_t* p) const
  {
    store(p, x);
    store(p + 4, y);
    store(p + 8, z);
    store(p + 12, intensity);
    p[14] = bits;
    p[15] = classification;
    p[16] = scan_angle;
    p[17] = user_data;
    store(p + 18, point_source);
  }
  unsigned returnNumber() const { return bits & 7u; }
  unsigned numberOfReturns() const { return (bits >> 3) & 7u; }
  unsigned scanDirection() const { return (bits >> 6) & 1u; }
};

class Point10V2 final : public PointwiseItemDecoder {
 public:
  void first(const std::uint8_t* raw) override
  {
    last_.read(raw);
    last_.intensity = 0; // the encoder predicts the second intensity from 0
  }

  void next(ArithmeticDecoder& dec, std::uint8_t* out) override
  {
    const std::uint32_t changed = dec.decodeSymbol(changed_values_);
    if (changed & (1u << 5))
      last_.bits = static_cast<std::uint8_t>(dec.decodeSymbol(bit_byte_[last_.bits]));
    const unsigned r = last_.returnNumber(), n = last_.numberOfReturns();
    const unsigned m = NUMBER_RETURN_MAP[n][r], l = returnLevel(n, r, 7);
    if (changed != 0) {
      if (changed & (1u << 4)) {
        last_.intensity = static_cast<std::uint16_t>(
            intensity_.decode(dec, last_intensity_[m], m < 3 ? m : 3));
        last_intensity_[m] = last_.intensity;
      } else {
        last_.intensity = last_intensity_[m];
      }
      if (changed & (1u << 3))
        last_.classification = static_cast<std::uint8_t>(
            dec.decodeSymbol(classification_[last_.classification]));
      if (changed & (1u << 2))
        last_.scan_angle = static_cast<std::uint8_t>(
            dec.decodeSymbol(scan_angle_[last_.scanDirection()]) + last_.scan_angle);
      if (changed & (1u << 1))
        last_.user_data =
            static_cast<std::uint8_t>(dec.decodeSymbol(user_data_[last_.user_data]));
      if (changed & 1u)
        last_.point_source = static_cast<std::uint16_t>(
            point_source_.decode(dec, last_.point_source, 0));
    }
    // x and y: difference from the median of the last five of this return context.
    std::int32_t diff = dx_.decode(dec, x_median_[m].get(), n == 1);
    last_.x = wrapAdd(last_.x, diff);
    x_median_[m].add(diff);
    std::uint32_t k = dx_.k();
    diff = dy_.decode(dec, y_median_[m].get(), (n == 1) + (k < 20 ? k & ~1u : 20));
    last_.y = wrapAdd(last_.y, diff);
    y_median_[m].add(diff);
    // z: from the last z of the same return level, in a context of the xy effort.
    k = (dx_.k() + dy_.k()) / 2;
    last_.z = z_.decode(dec, last_z_[l], (n == 1) + (k < 18 ? k & ~1u : 18));
    last_z_[l] = last_.z;
    last_.write(out);
  }

 private:
  Point10 last_;
  std::array<std::uint16_t, 16> last_intensity_{};
  std::array<Median5, 16> x_median_, y_median_;
  std::array<std::int32_t, 8> last_z_{};
  SymbolModel changed_values_{64};
  LazyModels scan_angle_{2, 256}, bit_byte_{256, 256}, classification_{256, 256},
      user_data_{256, 256};
  IntegerDecoder intensity_{16, 4}, point_source_{16}, dx_{32, 2}, dy_{32, 22},
      z_{32, 20};
};

// GPS time: up to four interleaved sequences of regular increments (multi-return
// pulses, several scanners); a symbol says which sequence and how far the time moved.
constexpr std::int32_t GPS_MULTI = 500;
constexpr std::int32_t GPS_MULTI_MINUS = -10;
constexpr std::int32_t GPS_MULTI_UNCHANGED = GPS_MULTI - GPS_MULTI_MINUS + 1;
constexpr std::int32_t GPS_MULTI_CODE_FULL = GPS_MULTI - GPS_MULTI_MINUS + 2;
constexpr std::int32_t GPS_MULTI_TOTAL = GPS_MULTI - GPS_MULTI_MINUS + 6;

class GpsTime11V2 final : public PointwiseItemDecoder {
 public:
  void first(const std::uint8_t* raw) override { time_[0] = load<std::int64_t>(raw); }

  void next(ArithmeticDecoder& dec, std::uint8_t* out) override
  {
    // A sequence switch is followed by the time of the new sequence; a corrupt
    // stream could ask for switches forever, so they are bounded.
    for (int guard = 0; guard < 8; ++guard)
      if (decodeOnce(dec))
        break;
    store(out, time_[last_]);
  }

 private:
  /// False when the symbol only switched sequences.
  bool decodeOnce(ArithmeticDecoder& dec)
  {
    if (diff_[last_] == 0) {
      const std::int32_t multi =
          static_cast<std::int32_t>(dec.decodeSymbol(zero_diff_));
      if (multi == 1) { // a 32-bit difference
        diff_[last_] = gps_.decode(dec, 0, 0);
        time_[last_] = wrapAdd64(time_[last_], diff_[last_]);
        extreme_[last_] = 0;
      } else if (multi == 2) { // a full new time
        fullTime(dec);
      } else if (multi > 2) {
        last_ = (last_ + static_cast<unsigned>(multi) - 2) & 3;
        return false;
      }
      return true;
    }
    const std::int32_t multi = static_cast<std::int32_t>(dec.decodeSymbol(multi_));
    if (multi == 1) {
      time_[last_] = wrapAdd64(time_[last_], gps_.decode(dec, diff_[last_], 1));
      extreme_[last_] = 0;
    } else if (multi < GPS_MULTI_UNCHANGED) {
      std::int32_t d;
      if (multi == 0) {
        d = gps_.decode(dec, 0, 7);
        countExtreme(d);
      } else if (multi < GPS_MULTI) {
        d = gps_.decode(dec, wrapMul(multi, diff_[last_]), multi < 10 ? 2 : 3);
      } else if (multi == GPS_MULTI) {
        d = gps_.decode(dec, wrapMul(GPS_MULTI, diff_[last_]), 4);
        countExtreme(d);
      } else {
        const std::int32_t minus = GPS_MULTI - multi;
        if (minus > GPS_MULTI_MINUS) {
          d = gps_.decode(dec, wrapMul(minus, diff_[last_]), 5);
        } else {
          d = gps_.decode(dec, wrapMul(GPS_MULTI_MINUS, diff_[last_]), 6);
          countExtreme(d);
        }
      }
      time_[last_] = wrapAdd64(time_[last_], d);
    } else if (multi == GPS_MULTI_CODE_FULL) {
      fullTime(dec);
    } else if (multi > GPS_MULTI_CODE_FULL) {
      last_ = (last_ + static_cast<unsigned>(multi - GPS_MULTI_CODE_FULL)) & 3;
      return false;
    }
    return true;
  }
  /// Three unusual differences in a row become the sequence's new difference.
  void countExtreme(std::int32_t d)
  {
    if (++extreme_[last_] > 3) {
      diff_[last_] = d;
      extreme_[last_] = 0;
    }
  }
  void fullTime(ArithmeticDecoder& dec)
  {
    next_ = (next_ + 1) & 3;
    const std::int32_t high =
        gps_.decode(dec, static_cast<std::int32_t>(time_[last_] >> 32), 8);
    time_[next_] = static_cast<std::int64_t>(
        (static_cast<std::uint64_t>(static_cast<std::uint32_t>(high)) << 32) |
        dec.readInt());
    last_ = next_;
    diff_[last_] = 0;
    extreme_[last_] = 0;
  }

  std::array<std::int64_t, 4> time_{}; // the bits of the doubles, as integers
  std::array<std::int32_t, 4> diff_{};
  std::array<std::int32_t, 4> extreme_{};
  unsigned last_ = 0, next_ = 0;
  SymbolModel multi_{GPS_MULTI_TOTAL}, zero_diff_{6};
  IntegerDecoder gps_{32, 9};
};

class Rgb12V2 final : public PointwiseItemDecoder {
 public:
  void first(const std::uint8_t* raw) override
  {
    for (int c = 0; c < 3; ++c)
      last_[c] = load<std::uint16_t>(raw + 2 * c);
  }
  void next(ArithmeticDecoder& dec, std::uint8_t* out) override
  {
    decodeRgb(dec, models_, last_, out);
  }

 private:
  std::array<std::uint16_t, 3> last_{};
  RgbModels models_;
};

class BytesV2 final : public PointwiseItemDecoder {
 public:
  explicit BytesV2(std::size_t count)
      : last_(count)
      , models_(count, SymbolModel(256))
  {}
  void first(const std::uint8_t* raw) override
  {
    last_.assign(raw, raw + last_.size());
  }
  void next(ArithmeticDecoder& dec, std::uint8_t* out) override
  {
    for (std::size_t i = 0; i < last_.size(); ++i) {
      last_[i] = static_cast<std::uint8_t>(last_[i] + dec.decodeSymbol(models_[i]));
      out[i] = last_[i];
    }
  }

 private:
  std::vector<std::uint8_t> last_;
  std::vector<SymbolModel> models_;
};

} // namespace

void decodeRgb(ArithmeticDecoder& dec, RgbModels& s, std::array<std::uint16_t, 3>& last,
               std::uint8_t* out)
{
  const std::uint32_t sym = dec.decodeSymbol(s.used);
  const auto low = [](std::uint16_t v) { return static_cast<int>(v & 0xFF); };
  const auto high = [](std::uint16_t v) { return static_cast<int>(v >> 8); };
  const auto byteSum = [](int a, int b) {
    return static_cast<std::uint16_t>(static_cast<std::uint8_t>(a + b));
  };
  std::uint16_t r, g, b;
  r = (sym & 1u) ? byteSum(static_cast<int>(dec.decodeSymbol(s.diff[0])), low(last[0]))
                 : static_cast<std::uint16_t>(low(last[0]));
  if (sym & 2u)
    r |= static_cast<std::uint16_t>(
        byteSum(static_cast<int>(dec.decodeSymbol(s.diff[1])), high(last[0])) << 8);
  else
    r |= static_cast<std::uint16_t>(last[0] & 0xFF00);
  if (sym & (1u << 6)) { // green and blue differ from red
    int diff = low(r) - low(last[0]);
    if (sym & (1u << 2))
      g = byteSum(static_cast<int>(dec.decodeSymbol(s.diff[2])),
                  clampByte(diff + low(last[1])));
    else
      g = static_cast<std::uint16_t>(low(last[1]));
    if (sym & (1u << 4)) {
      const int corr = static_cast<int>(dec.decodeSymbol(s.diff[4]));
      diff = (diff + low(g) - low(last[1])) / 2;
      b = byteSum(corr, clampByte(diff + low(last[2])));
    } else {
      b = static_cast<std::uint16_t>(low(last[2]));
    }
    diff = high(r) - high(last[0]);
    if (sym & (1u << 3))
      g |= static_cast<std::uint16_t>(
          byteSum(static_cast<int>(dec.decodeSymbol(s.diff[3])),
                  clampByte(diff + high(last[1])))
          << 8);
    else
      g |= static_cast<std::uint16_t>(last[1] & 0xFF00);
    if (sym & (1u << 5)) {
      const int corr = static_cast<int>(dec.decodeSymbol(s.diff[5]));
      diff = (diff + high(g) - high(last[1])) / 2;
      b |= static_cast<std::uint16_t>(byteSum(corr, clampByte(diff + high(last[2])))
                                      << 8);
    } else {
      b |= static_cast<std::uint16_t>(last[2] & 0xFF00);
    }
  } else { // grey
    g = r;
    b = r;
  }
  last = {r, g, b};
  for (int c = 0; c < 3; ++c)
    store(out + 2 * c, last[c]);
}

std::unique_ptr<PointwiseItemDecoder> makePoint10V2()
{
  return std::make_unique<Point10V2>();
}
std::unique_ptr<PointwiseItemDecoder> makeGpsTime11V2()
{
  return std::make_unique<GpsTime11V2>();
}
std::unique_ptr<PointwiseItemDecoder> makeRgb12V2()
{
  return std::make_unique<Rgb12V2>();
}
std::unique_ptr<PointwiseItemDecoder> makeBytesV2(std::size_t count)
{
  return std::make_unique<BytesV2>(count);
}

} // namespace laz
} // namespace pcl_vts
