// Version 1 pointwise items (LASzip 1.x, compressor 1): POINT10, GPSTIME11, RGB12,
// BYTE. Simpler predictions than version 2: the median of the last three x and y
// differences, integer-coded bytes. See item_decoder.h.
#include "integer_decoder.h"
#include "item_decoder.h"
#include "item_state.h"

namespace pcl_vts {
namespace laz {
namespace {

/// Median of three.
std::int32_t median3(const std::array<std::int32_t, 3>& v)
{
  if (v[0] < v[1])
    return v[1] < v[2] ? v[1] : v[0] < v[2] ? v[2] : v[0];
  return v[0] < v[2] ? v[0] : v[1] < v[2] ? v[2] : v[1];
}

class Point10V1 final : public PointwiseItemDecoder {
 public:
  void first(const std::uint8_t* raw) override { std::memcpy(last_, raw, 20); }

  void next(ArithmeticDecoder& dec, std::uint8_t* out) override
  {
    const std::int32_t dx = dx_.decode(dec, median3(x_diff_), 0);
    store(last_, wrapAdd(load<std::int32_t>(last_), dx));
    std::uint32_t k = dx_.k();
    const std::int32_t dy = dy_.decode(dec, median3(y_diff_), k < 19 ? k : 19);
    store(last_ + 4, wrapAdd(load<std::int32_t>(last_ + 4), dy));
    k = (k + dy_.k()) / 2;
    store(last_ + 8, z_.decode(dec, load<std::int32_t>(last_ + 8), k < 19 ? k : 19));
    const std::uint32_t changed = dec.decodeSymbol(changed_values_);
    if (changed != 0) {
      if (changed & 32u)
        store(last_ + 12, static_cast<std::uint16_t>(intensity_.decode(
                              dec, load<std::uint16_t>(last_ + 12), 0)));
      if (changed & 16u)
        last_[14] = static_cast<std::uint8_t>(dec.decodeSymbol(bit_byte_[last_[14]]));
      if (changed & 8u)
        last_[15] =
            static_cast<std::uint8_t>(dec.decodeSymbol(classification_[last_[15]]));
      if (changed & 4u)
        last_[16] =
            static_cast<std::uint8_t>(scan_angle_.decode(dec, last_[16], k < 3));
      if (changed & 2u)
        last_[17] = static_cast<std::uint8_t>(dec.decodeSymbol(user_data_[last_[17]]));
      if (changed & 1u)
        store(last_ + 18, static_cast<std::uint16_t>(point_source_.decode(
                              dec, load<std::uint16_t>(last_ + 18), 0)));
    }
    x_diff_[incr_] = dx;
    y_diff_[incr_] = dy;
    incr_ = (incr_ + 1) % 3;
    std::memcpy(out, last_, 20);
  }

 private:
  std::uint8_t last_[20] = {};
  std::array<std::int32_t, 3> x_diff_{}, y_diff_{};
  unsigned incr_ = 0;
  SymbolModel changed_values_{64};
  LazyModels bit_byte_{256, 256}, classification_{256, 256}, user_data_{256, 256};
  IntegerDecoder dx_{32}, dy_{32, 20}, z_{32, 20}, intensity_{16}, scan_angle_{8, 2},
      point_source_{16};
};

constexpr std::uint32_t GPS_MULTI_MAX = 512;

class GpsTime11V1 final : public PointwiseItemDecoder {
 public:
  void first(const std::uint8_t* raw) override { time_ = load<std::int64_t>(raw); }

  void next(ArithmeticDecoder& dec, std::uint8_t* out) override
  {
    if (diff_ == 0) {
      const std::uint32_t multi = dec.decodeSymbol(zero_diff_);
      if (multi == 1) { // a 32-bit difference
        diff_ = gps_.decode(dec, 0, 0);
        time_ = wrapAdd64(time_, diff_);
      } else if (multi == 2) { // a full new time
        time_ = readInt64(dec);
      }
    } else {
      const std::uint32_t multi = dec.decodeSymbol(multi_);
      if (multi < GPS_MULTI_MAX - 2) {
        std::int32_t d;
        if (multi == 1) {
          d = gps_.decode(dec, diff_, 1);
          diff_ = d;
          extreme_ = 0;
        } else if (multi == 0) {
          d = gps_.decode(dec, diff_ / 4, 2);
          countExtreme(d);
        } else {
          const auto m = static_cast<std::int32_t>(multi);
          d = gps_.decode(dec, wrapMul(m, diff_), multi < 10 ? 3 : multi < 50 ? 4 : 5);
          if (multi == GPS_MULTI_MAX - 3)
            countExtreme(d);
        }
        time_ = wrapAdd64(time_, d);
      } else if (multi < GPS_MULTI_MAX - 1) {
        time_ = readInt64(dec);
      }
    }
    store(out, time_);
  }

 private:
  static std::int64_t readInt64(ArithmeticDecoder& dec)
  {
    const std::uint64_t low = dec.readInt();
    return static_cast<std::int64_t>((static_cast<std::uint64_t>(dec.readInt()) << 32) |
                                     low);
  }
  void countExtreme(std::int32_t d)
  {
    if (++extreme_ > 3) {
      diff_ = d;
      extreme_ = 0;
    }
  }

  std::int64_t time_ = 0;
  std::int32_t diff_ = 0, extreme_ = 0;
  SymbolModel multi_{GPS_MULTI_MAX}, zero_diff_{3};
  IntegerDecoder gps_{32, 6};
};

class Rgb12V1 final : public PointwiseItemDecoder {
 public:
  void first(const std::uint8_t* raw) override
  {
    for (int c = 0; c < 3; ++c)
      last_[c] = load<std::uint16_t>(raw + 2 * c);
  }
  void next(ArithmeticDecoder& dec, std::uint8_t* out) override
  {
    const std::uint32_t sym = dec.decodeSymbol(used_);
    for (unsigned c = 0; c < 3; ++c) {
      const unsigned low_bit = 2 * c, high_bit = 2 * c + 1;
      std::uint16_t v =
          (sym & (1u << low_bit))
              ? static_cast<std::uint16_t>(rgb_.decode(dec, last_[c] & 0xFF, low_bit))
              : static_cast<std::uint16_t>(last_[c] & 0xFF);
      if (sym & (1u << high_bit))
        v |= static_cast<std::uint16_t>(rgb_.decode(dec, last_[c] >> 8, high_bit) << 8);
      else
        v |= static_cast<std::uint16_t>(last_[c] & 0xFF00);
      last_[c] = v;
      store(out + 2 * c, v);
    }
  }

 private:
  std::array<std::uint16_t, 3> last_{};
  SymbolModel used_{64};
  IntegerDecoder rgb_{8, 6};
};

class BytesV1 final : public PointwiseItemDecoder {
 public:
  explicit BytesV1(std::size_t count)
      : last_(count)
      , bytes_(8, static_cast<std::uint32_t>(count))
  {}
  void first(const std::uint8_t* raw) override
  {
    last_.assign(raw, raw + last_.size());
  }
  void next(ArithmeticDecoder& dec, std::uint8_t* out) override
  {
    for (std::size_t i = 0; i < last_.size(); ++i) {
      last_[i] = static_cast<std::uint8_t>(
          bytes_.decode(dec, last_[i], static_cast<std::uint32_t>(i)));
      out[i] = last_[i];
    }
  }

 private:
  std::vector<std::uint8_t> last_;
  IntegerDecoder bytes_;
};

} // namespace

std::unique_ptr<PointwiseItemDecoder> makePoint10V1()
{
  return std::make_unique<Point10V1>();
}
std::unique_ptr<PointwiseItemDecoder> makeGpsTime11V1()
{
  return std::make_unique<GpsTime11V1>();
}
std::unique_ptr<PointwiseItemDecoder> makeRgb12V1()
{
  return std::make_unique<Rgb12V1>();
}
std::unique_ptr<PointwiseItemDecoder> makeBytesV1(std::size_t count)
{
  return std::make_unique<BytesV1>(count);
}

} // namespace laz
} // namespace pcl_vts
