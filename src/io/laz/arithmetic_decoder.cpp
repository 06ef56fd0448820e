// Symbol models and symbol decoding of the LASzip range decoder; see
// arithmetic_decoder.h.
#include "arithmetic_decoder.h"

namespace pcl_vts {
namespace laz {

SymbolModel::SymbolModel(std::uint32_t n)
    : symbols(n)
    , last_symbol(n - 1)
{
  if (symbols > 16) {
    std::uint32_t table_bits = 3;
    while (symbols > (1u << (table_bits + 2)))
      ++table_bits;
    table_size = 1u << table_bits;
    table_shift = SYMBOL_LENGTH_SHIFT - table_bits;
    decoder_table.assign(table_size + 2, 0);
  }
  distribution.assign(symbols, 0);
  symbol_count.assign(symbols, 1);
  update_cycle = symbols;
  update();
  symbols_until_update = update_cycle = (symbols + 6) >> 1;
}

void SymbolModel::update()
{
  if ((total_count += update_cycle) > SYMBOL_MAX_COUNT) { // halve the counts
    total_count = 0;
    for (std::uint32_t n = 0; n < symbols; ++n)
      total_count += (symbol_count[n] = (symbol_count[n] + 1) >> 1);
  }
  const std::uint32_t scale = 0x80000000u / total_count;
  std::uint32_t sum = 0, s = 0;
  for (std::uint32_t k = 0; k < symbols; ++k) {
    distribution[k] = (scale * sum) >> (31 - SYMBOL_LENGTH_SHIFT);
    sum += symbol_count[k];
    if (table_size != 0) {
      const std::uint32_t w = distribution[k] >> table_shift;
      while (s < w)
        decoder_table[++s] = k - 1;
    }
  }
  if (table_size != 0) {
    decoder_table[0] = 0;
    while (s <= table_size)
      decoder_table[++s] = symbols - 1;
  }
  update_cycle = (5 * update_cycle) >> 2;
  const std::uint32_t max_cycle = (symbols + 6) << 3;
  if (update_cycle > max_cycle)
    update_cycle = max_cycle;
  symbols_until_update = update_cycle;
}

std::uint32_t ArithmeticDecoder::decodeSymbol(SymbolModel& m)
{
  std::uint32_t sym, x, y = length_;
  if (!m.decoder_table.empty()) { // table lookup, then bisection
    const std::uint32_t dv = value_ / (length_ >>= SYMBOL_LENGTH_SHIFT);
    std::uint32_t t = dv >> m.table_shift;
    if (t > m.table_size) // only a corrupt stream gets here
      t = m.table_size;
    sym = m.decoder_table[t];
    std::uint32_t n = m.decoder_table[t + 1] + 1;
    while (n > sym + 1) {
      const std::uint32_t k = (sym + n) >> 1;
      if (m.distribution[k] > dv)
        n = k;
      else
        sym = k;
    }
    x = m.distribution[sym] * length_;
    if (sym != m.last_symbol)
      y = m.distribution[sym + 1] * length_;
  } else { // small alphabet: bisection with multiplications
    x = sym = 0;
    length_ >>= SYMBOL_LENGTH_SHIFT;
    std::uint32_t n = m.symbols;
    std::uint32_t k = n >> 1;
    do {
      const std::uint32_t z = length_ * m.distribution[k];
      if (z > value_) {
        n = k;
        y = z;
      } else {
        sym = k;
        x = z;
      }
    } while ((k = (sym + n) >> 1) != sym);
  }
  value_ -= x;
  length_ = y - x;
  if (length_ < MIN_LENGTH)
    renormalise();
  ++m.symbol_count[sym];
  if (--m.symbols_until_update == 0)
    m.update();
  return sym;
}

} // namespace laz
} // namespace pcl_vts
