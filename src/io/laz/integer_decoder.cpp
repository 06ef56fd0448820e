#include "integer_decoder.h"

#include <algorithm>
#include <limits>

namespace pcl_vts {
namespace laz {

IntegerDecoder::IntegerDecoder(std::uint32_t bits, std::uint32_t contexts,
                               std::uint32_t bits_high)
    : bits_high_(bits_high)
{
  if (bits != 0 && bits < 32) {
    corr_bits_ = bits;
    corr_range_ = 1u << bits;
    corr_min_ = -static_cast<std::int32_t>(corr_range_ / 2);
  } else {
    corr_bits_ = 32;
    corr_range_ = 0;
    corr_min_ = std::numeric_limits<std::int32_t>::min();
  }
  k_models_.assign(contexts, SymbolModel(corr_bits_ + 1));
  for (std::uint32_t i = 1; i <= corr_bits_; ++i)
    corrector_models_.emplace_back(i <= bits_high_ ? 1u << i : 1u << bits_high_);
}

std::int32_t IntegerDecoder::corrector(ArithmeticDecoder& dec, std::uint32_t context)
{
  k_ = dec.decodeSymbol(k_models_[context]);
  if (k_ == 0) // the corrector is 0 or 1
    return static_cast<std::int32_t>(dec.decodeBit(corrector0_));
  if (k_ >= 32)
    return corr_min_;
  std::uint32_t c;
  if (k_ <= bits_high_) {
    c = dec.decodeSymbol(corrector_models_[k_ - 1]);
  } else { // the high bits by the model, the low k - bits_high raw
    const std::uint32_t low_bits = k_ - bits_high_;
    c = dec.decodeSymbol(corrector_models_[k_ - 1]);
    c = (c << low_bits) | dec.readBits(low_bits);
  }
  // [0, 2^(k-1)) holds -(2^k - 1) .. -2^(k-1); [2^(k-1), 2^k) holds 2^(k-1)+1 .. 2^k.
  if (c >= (1u << (k_ - 1)))
    return static_cast<std::int32_t>(c + 1);
  return static_cast<std::int32_t>(c - ((1u << k_) - 1));
}

} // namespace laz
} // namespace pcl_vts
