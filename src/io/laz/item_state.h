// Small pieces of state the LASzip item decoders share: the median of the last five
// coordinate differences, models made on first use (most contexts never occur), the
// return-number contexts, and little-endian record fields.
#pragma once

#include "arithmetic_decoder.h"

#include <array>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

namespace pcl_vts {
namespace laz {

/// Median of the last five values, kept sorted with a flag for which side the next
/// insertion replaces (LASzip's StreamingMedian5).
class Median5 {
 public:
  std::int32_t get() const { return v_[2]; }
  void add(std::int32_t x)
  {
    if (high_) {
      if (x < v_[2]) {
        v_[4] = v_[3];
        v_[3] = v_[2];
        if (x < v_[0]) {
          v_[2] = v_[1];
          v_[1] = v_[0];
          v_[0] = x;
        } else if (x < v_[1]) {
          v_[2] = v_[1];
          v_[1] = x;
        } else {
          v_[2] = x;
        }
      } else {
        if (x < v_[3]) {
          v_[4] = v_[3];
          v_[3] = x;
        } else {
          v_[4] = x;
        }
        high_ = false;
      }
    } else {
      if (v_[2] < x) {
        v_[0] = v_[1];
        v_[1] = v_[2];
        if (v_[4] < x) {
          v_[2] = v_[3];
          v_[3] = v_[4];
          v_[4] = x;
        } else if (v_[3] < x) {
          v_[2] = v_[3];
          v_[3] = x;
        } else {
          v_[2] = x;
        }
      } else {
        if (v_[1] < x) {
          v_[0] = v_[1];
          v_[1] = x;
        } else {
          v_[0] = x;
        }
        high_ = true;
      }
    }
  }

 private:
  std::array<std::int32_t, 5> v_{};
  bool high_ = true;
};

/// count models of `symbols` symbols, each made when first used.
class LazyModels {
 public:
  LazyModels(std::size_t count, std::uint32_t symbols)
      : models_(count)
      , symbols_(symbols)
  {}
  SymbolModel& operator[](std::size_t i)
  {
    if (!models_[i])
      models_[i] = std::make_unique<SymbolModel>(symbols_);
    return *models_[i];
  }

 private:
  std::vector<std::unique_ptr<SymbolModel>> models_;
  std::uint32_t symbols_;
};

/// |n - r| capped at `cap`: the z and intensity contexts of return r of n.
inline unsigned returnLevel(unsigned n, unsigned r, unsigned cap)
{
  const unsigned d = n > r ? n - r : r - n;
  return d < cap ? d : cap;
}

/// Wrapping int32 sum (LAS coordinates wrap in LASzip's arithmetic).
inline std::int32_t wrapAdd(std::int32_t a, std::int32_t b)
{
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(a) +
                                   static_cast<std::uint32_t>(b));
}
inline std::int64_t wrapAdd64(std::int64_t a, std::int64_t b)
{
  return static_cast<std::int64_t>(static_cast<std::uint64_t>(a) +
                                   static_cast<std::uint64_t>(b));
}
inline std::int32_t wrapMul(std::int32_t a, std::int32_t b)
{
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(a) *
                                   static_cast<std::uint32_t>(b));
}

template <typename T>
T load(const std::uint8_t* p)
{
  T v;
  std::memcpy(&v, p, sizeof(T)); // LAZ runs on little-endian hosts only (checked)
  return v;
}
template <typename T>
void store(std::uint8_t* p, T v)
{
  std::memcpy(p, &v, sizeof(T));
}

/// Clamps to a byte, as the RGB predictions do.
inline std::uint8_t clampByte(int v)
{
  return static_cast<std::uint8_t>(v < 0 ? 0 : v > 255 ? 255 : v);
}

/// RGB12 v2 and RGB14 v3: which of the six colour bytes changed, then each changed
/// byte's difference from a prediction that follows red's change.
struct RgbModels {
  SymbolModel used{128};
  std::array<SymbolModel, 6> diff{SymbolModel(256), SymbolModel(256), SymbolModel(256),
                                  SymbolModel(256), SymbolModel(256), SymbolModel(256)};
};

/// Decodes one RGB triple into out (6 bytes), predicted from `last`, which it then
/// updates; RGB14 keeps `last` and the models in different scanner contexts.
void decodeRgb(ArithmeticDecoder& dec, RgbModels& models,
               std::array<std::uint16_t, 3>& last, std::uint8_t* out);

} // namespace laz
} // namespace pcl_vts
