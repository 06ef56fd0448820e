// LASzip's integer decompressor: a value is coded as a prediction plus a corrector;
// the corrector's bit length k is an adaptive symbol (per context), then its bits
// follow, the top ones modelled and the rest raw. The result wraps into the
// corrector range, as the encoder folded it.
#pragma once

#include "arithmetic_decoder.h"

#include <cstdint>
#include <vector>

namespace pcl_vts {
namespace laz {

class IntegerDecoder {
 public:
  /// bits: width of the values (32 = the whole int32 range); contexts: how many
  /// independent k models; bits_high: corrector bits coded by a model, the rest raw.
  explicit IntegerDecoder(std::uint32_t bits = 16, std::uint32_t contexts = 1,
                          std::uint32_t bits_high = 8);

  std::int32_t decode(ArithmeticDecoder& dec, std::int32_t prediction,
                      std::uint32_t context)
  {
    const std::uint32_t real = static_cast<std::uint32_t>(prediction) +
                               static_cast<std::uint32_t>(corrector(dec, context));
    std::int32_t value = static_cast<std::int32_t>(real);
    if (corr_range_ != 0) { // fold back into [0, range)
      if (value < 0)
        value = static_cast<std::int32_t>(real + corr_range_);
      else if (real >= corr_range_)
        value = static_cast<std::int32_t>(real - corr_range_);
    }
    return value;
  }

  /// Bit length of the last corrector: the next values' contexts depend on it.
  std::uint32_t k() const { return k_; }

 private:
  std::int32_t corrector(ArithmeticDecoder& dec, std::uint32_t context);

  std::uint32_t bits_high_;
  std::uint32_t corr_bits_, corr_range_;
  std::int32_t corr_min_;
  std::uint32_t k_ = 0;
  std::vector<SymbolModel> k_models_;         // one per context
  BitModel corrector0_;                       // k == 0: the corrector is 0 or 1
  std::vector<SymbolModel> corrector_models_; // k == 1..corr_bits
};

} // namespace laz
} // namespace pcl_vts
