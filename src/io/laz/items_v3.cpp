// Version 3 layered items (LASzip 3.x, LAS 1.4 point formats 6-8): POINT14, RGB14,
// RGBNIR14, BYTE14. Every field group has its own stream in the chunk, and the state
// is kept per scanner channel (up to four scanners interleave in one file). An empty
// layer means the field never changed in the chunk.
#include "integer_decoder.h"
#include "item_decoder.h"
#include "item_state.h"

#include <algorithm>
#include <cstring>

namespace pcl_vts {
namespace laz {
namespace {

// x/y context of return r of n (formats 6-10, up to 15 returns).
constexpr std::uint8_t NUMBER_RETURN_MAP_6CTX[16][16] = {
    {0, 1, 2, 3, 4, 5, 3, 4, 4, 5, 5, 5, 5, 5, 5, 5},
    {1, 0, 1, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3},
    {2, 1, 2, 4, 4, 4, 4, 4, 4, 4, 4, 3, 3, 3, 3, 3},
    {3, 3, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {4, 3, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {5, 3, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {3, 3, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {4, 3, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4},
    {4, 3, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4},
    {5, 3, 4, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4},
    {5, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 4, 4, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5, 4, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5}};

constexpr std::int32_t GPS_MULTI = 500;
constexpr std::int32_t GPS_MULTI_MINUS = -10;
constexpr std::int32_t GPS_MULTI_CODE_FULL = GPS_MULTI - GPS_MULTI_MINUS + 1;

/// The 30 bytes of a point format 6 record.
struct Point14 {
  std::int32_t x = 0, y = 0, z = 0;
  std::uint16_t intensity = 0;
  std::uint8_t returns = 0; // return number 0-3, number of returns 4-7
  std::uint8_t flags = 0;   // class flags 0-3, scanner channel 4-5, scan dir, edge
  std::uint8_t classification = 0, user_data = 0;
  std::int16_t scan_angle = 0;
  std::uint16_t point_source = 0;
  std::int64_t gps_time = 0; // the double's bits

  void read(const std::uint8_t* p)
  {
    x = load<std::int32_t>(p);
    y = load<std::int32_t>(p + 4);
    z = load<std::int32_t>(p + 8);
    intensity = load<std::uint16_t>(p + 12);
    returns = p[14];
    flags = p[15];
    classification = p[16];
    user_data = p[17];
    scan_angle = load<std::int16_t>(p + 18);
    point_source = load<std::uint16_t>(p + 20);
    gps_time = load<std::int64_t>(p + 22);
  }
  void write(std::uint8_t* p) const
  {
    store(p, x);
    store(p + 4, y);
    store(p + 8, z);
    store(p + 12, intensity);
    p[14] = returns;
    p[15] = flags;
    p[16] = classification;
    p[17] = user_data;
    store(p + 18, scan_angle);
    store(p + 20, point_source);
    store(p + 22, gps_time);
  }
  unsigned returnNumber() const { return returns & 0x0Fu; }
  unsigned numberOfReturns() const { return returns >> 4; }
  unsigned channel() const { return (flags >> 4) & 3u; }
};

/// One layer: its decoder, started only when the layer holds bytes.
struct Layer {
  ArithmeticDecoder dec;
  bool present = false;
  void start(const std::uint8_t* data, std::uint32_t size)
  {
    present = size != 0;
    if (present)
      dec.start(data, data + size);
  }
};

/// True when every present layer decoded to its last byte and not beyond.
template <typename Layers>
bool consumedExactly(const Layers& layers)
{
  for (const Layer& l : layers)
    if (l.present && (l.dec.overrun() != 0 || l.dec.unread() != 0))
      return false;
  return true;
}

template <typename Layers>
bool overran(const Layers& layers)
{
  for (const Layer& l : layers)
    if (l.present && l.dec.overrun() != 0)
      return true;
  return false;
}

class Point14V3 final : public LayeredItemDecoder {
  enum {
    XY,
    Z,
    CLASS,
    FLAGS,
    INTENSITY,
    SCAN_ANGLE,
    USER_DATA,
    POINT_SOURCE,
    GPS_TIME,
    COUNT
  };

  /// Everything kept per scanner channel.
  struct Channel {
    bool used = false;
    Point14 last;
    std::array<std::uint16_t, 8> last_intensity{};
    std::array<std::int32_t, 8> last_z{};
    std::array<Median5, 12> x_median, y_median;
    unsigned gps_last = 0, gps_next = 0;
    std::array<std::int64_t, 4> gps{};
    std::array<std::int32_t, 4> gps_diff{}, gps_extreme{};
    bool gps_changed = false;
    LazyModels changed_values{8, 128};
    SymbolModel scanner_channel{3}, rn_gps_same{13};
    LazyModels nr{16, 16}, rn{16, 16}, classification{64, 256}, flag{64, 64},
        user_data{64, 256};
    SymbolModel gps_multi{515}, gps_0diff{5};
    IntegerDecoder dx{32, 2}, dy{32, 22}, z{32, 20}, intensity{16, 4},
        scan_angle{16, 2}, point_source{16}, gps_time{32, 9};

    /// A channel's state starts from the record before its first one.
    void begin(const Point14& p)
    {
      used = true;
      last = p;
      last_z.fill(p.z);
      last_intensity.fill(p.intensity);
      gps[0] = p.gps_time;
    }
  };

 public:
  void first(const std::uint8_t* raw, unsigned& context) override
  {
    Point14 p;
    p.read(raw);
    context = current_ = p.channel();
    channel(current_).begin(p);
  }
  explicit Point14V3(bool position_only)
      : position_only_(position_only)
  {}
  std::size_t layers() const override { return COUNT; }
  void startLayers(const std::uint8_t* const* data, const std::uint32_t* sizes) override
  {
    for (int i = 0; i < COUNT; ++i)
      layer_[i].start(data[i], sizes[i]);
    // Position, returns and class: the other layers are left undecoded, as no field
    // read here depends on them (LASzip's selective decompression).
    if (position_only_)
      for (int i : {FLAGS, INTENSITY, SCAN_ANGLE, USER_DATA, POINT_SOURCE, GPS_TIME})
        layer_[i].present = false;
  }
  bool consumedExactly() const override { return laz::consumedExactly(layer_); }
  bool overran() const override { return laz::overran(layer_); }

  void next(std::uint8_t* out, unsigned& context) override
  {
    ArithmeticDecoder& xy = layer_[XY].dec;
    Channel& prev = channel(current_);
    const unsigned prev_r = prev.last.returnNumber(),
                   prev_n = prev.last.numberOfReturns();
    const unsigned change_context =
        (prev_r == 1) | ((prev_r >= prev_n) << 1) | (prev.gps_changed << 2);
    const std::uint32_t changed = xy.decodeSymbol(prev.changed_values[change_context]);
    const bool channel_changed = (changed >> 6) & 1,
               point_source_changed = (changed >> 5) & 1,
               gps_changed = (changed >> 4) & 1,
               scan_angle_changed = (changed >> 3) & 1, nr_changed = (changed >> 2) & 1,
               rn_minus = (changed >> 1) & 1, rn_plus = changed & 1;
    unsigned sc = current_;
    if (channel_changed) {
      sc = (sc + xy.decodeSymbol(prev.scanner_channel) + 1) % 4;
      current_ = sc;
    }
    context = sc;
    Channel& c = channel(sc);
    if (!c.used)
      c.begin(prev.last);
    Point14& p = c.last;
    p.flags = static_cast<std::uint8_t>((p.flags & ~0x30u) | (sc << 4));

    unsigned n = p.numberOfReturns(), r = p.returnNumber();
    if (nr_changed)
      n = xy.decodeSymbol(c.nr[n]);
    if (rn_plus && !rn_minus)
      r = (r + 1) % 16;
    else if (rn_minus && !rn_plus)
      r = (r + 15) % 16;
    else if (rn_plus && rn_minus)
      r = gps_changed ? xy.decodeSymbol(c.rn[r])
                      : (r + xy.decodeSymbol(c.rn_gps_same) + 2) % 16;
    p.returns = static_cast<std::uint8_t>((n << 4) | r);

    const unsigned xy_context = (NUMBER_RETURN_MAP_6CTX[n][r] << 1) | gps_changed;
    std::int32_t diff = c.dx.decode(xy, c.x_median[xy_context].get(), n == 1);
    p.x = wrapAdd(p.x, diff);
    c.x_median[xy_context].add(diff);
    std::uint32_t k = std::min(c.dx.k(), 20u) & ~1u;
    diff = c.dy.decode(xy, c.y_median[xy_context].get(), (n == 1) | k);
    p.y = wrapAdd(p.y, diff);
    c.y_median[xy_context].add(diff);

    if (layer_[Z].present) {
      k = std::min((c.dx.k() + c.dy.k()) / 2, 18u) & ~1u;
      const unsigned level = returnLevel(n, r, 7);
      p.z = c.z.decode(layer_[Z].dec, c.last_z[level], (n == 1) | k);
      c.last_z[level] = p.z;
    }
    if (layer_[CLASS].present) {
      const unsigned ctx = (r == 1 && r >= n) | ((p.classification & 0x1Fu) << 1);
      p.classification = static_cast<std::uint8_t>(
          layer_[CLASS].dec.decodeSymbol(c.classification[ctx]));
    }
    if (layer_[FLAGS].present) {
      const unsigned merged = (p.flags & 0x0Fu) | (((p.flags >> 6) & 3u) << 4);
      const std::uint32_t f = layer_[FLAGS].dec.decodeSymbol(c.flag[merged]);
      p.flags =
          static_cast<std::uint8_t>((f & 0x0Fu) | (sc << 4) | (((f >> 4) & 3u) << 6));
    }
    if (layer_[INTENSITY].present) {
      const unsigned ctx = gps_changed | ((r >= n) << 1) | ((r == 1) << 2);
      p.intensity = static_cast<std::uint16_t>(
          c.intensity.decode(layer_[INTENSITY].dec, c.last_intensity[ctx], ctx >> 1));
      c.last_intensity[ctx] = p.intensity;
    }
    if (scan_angle_changed && layer_[SCAN_ANGLE].present)
      p.scan_angle = static_cast<std::int16_t>(
          c.scan_angle.decode(layer_[SCAN_ANGLE].dec, p.scan_angle, gps_changed));
    if (layer_[USER_DATA].present)
      p.user_data = static_cast<std::uint8_t>(
          layer_[USER_DATA].dec.decodeSymbol(c.user_data[p.user_data / 4]));
    if (point_source_changed && layer_[POINT_SOURCE].present)
      p.point_source = static_cast<std::uint16_t>(
          c.point_source.decode(layer_[POINT_SOURCE].dec, p.point_source, 0));
    if (gps_changed && layer_[GPS_TIME].present)
      decodeGpsTime(c);
    c.gps_changed = gps_changed;
    p.write(out);
  }

 private:
  Channel& channel(unsigned i)
  {
    if (!channels_[i])
      channels_[i] = std::make_unique<Channel>();
    return *channels_[i];
  }

  void decodeGpsTime(Channel& c)
  {
    ArithmeticDecoder& dec = layer_[GPS_TIME].dec;
    for (int guard = 0; guard < 8; ++guard) { // sequence switches, bounded
      const unsigned s = c.gps_last;
      if (c.gps_diff[s] == 0) {
        const std::uint32_t multi = dec.decodeSymbol(c.gps_0diff);
        if (multi == 0) {
          c.gps_diff[s] = c.gps_time.decode(dec, 0, 0);
          c.gps[s] = wrapAdd64(c.gps[s], c.gps_diff[s]);
          c.gps_extreme[s] = 0;
        } else if (multi == 1) {
          fullGpsTime(c, dec);
        } else {
          c.gps_last = (s + multi - 1) & 3;
          continue;
        }
        break;
      }
      const std::int32_t multi =
          static_cast<std::int32_t>(dec.decodeSymbol(c.gps_multi));
      if (multi == 1) {
        c.gps[s] = wrapAdd64(c.gps[s], c.gps_time.decode(dec, c.gps_diff[s], 1));
        c.gps_extreme[s] = 0;
      } else if (multi < GPS_MULTI_CODE_FULL) {
        std::int32_t d;
        if (multi == 0) {
          d = c.gps_time.decode(dec, 0, 7);
          countExtreme(c, d);
        } else if (multi < GPS_MULTI) {
          d = c.gps_time.decode(dec, wrapMul(multi, c.gps_diff[s]), multi < 10 ? 2 : 3);
        } else if (multi == GPS_MULTI) {
          d = c.gps_time.decode(dec, wrapMul(GPS_MULTI, c.gps_diff[s]), 4);
          countExtreme(c, d);
        } else {
          const std::int32_t minus = GPS_MULTI - multi;
          if (minus > GPS_MULTI_MINUS) {
            d = c.gps_time.decode(dec, wrapMul(minus, c.gps_diff[s]), 5);
          } else {
            d = c.gps_time.decode(dec, wrapMul(GPS_MULTI_MINUS, c.gps_diff[s]), 6);
            countExtreme(c, d);
          }
        }
        c.gps[s] = wrapAdd64(c.gps[s], d);
      } else if (multi == GPS_MULTI_CODE_FULL) {
        fullGpsTime(c, dec);
      } else {
        c.gps_last = (s + static_cast<unsigned>(multi - GPS_MULTI_CODE_FULL)) & 3;
        continue;
      }
      break;
    }
    c.last.gps_time = c.gps[c.gps_last];
  }
  static void countExtreme(Channel& c, std::int32_t d)
  {
    const unsigned s = c.gps_last;
    if (++c.gps_extreme[s] > 3) {
      c.gps_extreme[s] = 0;
      c.gps_diff[s] = d;
    }
  }
  static void fullGpsTime(Channel& c, ArithmeticDecoder& dec)
  {
    c.gps_next = (c.gps_next + 1) & 3;
    const std::int32_t high = c.gps_time.decode(
        dec,
        static_cast<std::int32_t>(static_cast<std::uint64_t>(c.gps[c.gps_last]) >> 32),
        8);
    c.gps[c.gps_next] = static_cast<std::int64_t>(
        (static_cast<std::uint64_t>(static_cast<std::uint32_t>(high)) << 32) |
        dec.readInt());
    c.gps_last = c.gps_next;
    c.gps_diff[c.gps_last] = 0;
    c.gps_extreme[c.gps_last] = 0;
  }

  bool position_only_;
  std::array<Layer, COUNT> layer_;
  std::array<std::unique_ptr<Channel>, 4> channels_;
  unsigned current_ = 0;
};

/// Shared by RGB14, NIR14 and BYTE14: a value per channel used as the prediction,
/// with LASzip's rule that a switch to an already used channel keeps predicting
/// from the previous channel's value (and updates that one).
template <typename Value, typename Models>
class ChannelPrediction {
 public:
  void first(const Value& v, unsigned context)
  {
    current_ = context;
    slot(context).used = true;
    slot(context).last = v;
  }
  /// The value to predict from and the models to use for channel sc.
  std::pair<Value*, Models*> select(unsigned sc)
  {
    Value* last = &slot(current_).last;
    if (sc != current_) {
      current_ = sc;
      Slot& s = slot(sc);
      if (!s.used) {
        s.used = true;
        s.last = *last;
        last = &s.last;
      }
    }
    return {last, &slot(sc).models};
  }
  const Value& current() { return slot(current_).last; }

 private:
  struct Slot {
    bool used = false;
    Value last{};
    Models models;
  };
  Slot& slot(unsigned i)
  {
    if (!slots_[i])
      slots_[i] = std::make_unique<Slot>();
    return *slots_[i];
  }
  std::array<std::unique_ptr<Slot>, 4> slots_;
  unsigned current_ = 0;
};

struct NirModels {
  SymbolModel used{4};
  std::array<SymbolModel, 2> diff{SymbolModel(256), SymbolModel(256)};
};

class Rgb14V3 final : public LayeredItemDecoder {
  using Rgb = std::array<std::uint16_t, 3>;

 public:
  explicit Rgb14V3(bool with_nir)
      : with_nir_(with_nir)
  {}
  void first(const std::uint8_t* raw, unsigned& context) override
  {
    Rgb rgb;
    for (int c = 0; c < 3; ++c)
      rgb[c] = load<std::uint16_t>(raw + 2 * c);
    rgb_.first(rgb, context);
    if (with_nir_)
      nir_.first(load<std::uint16_t>(raw + 6), context);
  }
  std::size_t layers() const override { return with_nir_ ? 2 : 1; }
  void startLayers(const std::uint8_t* const* data, const std::uint32_t* sizes) override
  {
    layer_[0].start(data[0], sizes[0]);
    if (with_nir_)
      layer_[1].start(data[1], sizes[1]);
  }
  bool consumedExactly() const override { return laz::consumedExactly(layer_); }
  bool overran() const override { return laz::overran(layer_); }

  void next(std::uint8_t* out, unsigned& context) override
  {
    if (!layer_[0].present) {
      const Rgb& rgb = rgb_.current();
      for (int c = 0; c < 3; ++c)
        store(out + 2 * c, rgb[c]);
    } else {
      auto [last, models] = rgb_.select(context);
      decodeRgb(layer_[0].dec, *models, *last, out);
    }
    if (!with_nir_)
      return;
    if (!layer_[1].present) {
      store(out + 6, nir_.current());
      return;
    }
    auto [last, models] = nir_.select(context);
    ArithmeticDecoder& dec = layer_[1].dec;
    const std::uint32_t sym = dec.decodeSymbol(models->used);
    std::uint16_t v = (sym & 1u)
                          ? static_cast<std::uint8_t>(
                                dec.decodeSymbol(models->diff[0]) + (*last & 0xFFu))
                          : static_cast<std::uint16_t>(*last & 0xFFu);
    if (sym & 2u)
      v |= static_cast<std::uint16_t>(
          static_cast<std::uint8_t>(dec.decodeSymbol(models->diff[1]) + (*last >> 8))
          << 8);
    else
      v |= *last & 0xFF00u;
    *last = v;
    store(out + 6, v);
  }

 private:
  bool with_nir_;
  std::array<Layer, 2> layer_;
  ChannelPrediction<Rgb, RgbModels> rgb_;
  ChannelPrediction<std::uint16_t, NirModels> nir_;
};

class Bytes14V3 final : public LayeredItemDecoder {
  using Bytes = std::vector<std::uint8_t>;
  struct Models {
    std::vector<std::unique_ptr<SymbolModel>> byte;
  };

 public:
  explicit Bytes14V3(std::size_t count)
      : count_(count)
      , layer_(count)
  {}
  void first(const std::uint8_t* raw, unsigned& context) override
  {
    bytes_.first(Bytes(raw, raw + count_), context);
  }
  std::size_t layers() const override { return count_; }
  void startLayers(const std::uint8_t* const* data, const std::uint32_t* sizes) override
  {
    for (std::size_t i = 0; i < count_; ++i)
      layer_[i].start(data[i], sizes[i]);
  }
  bool consumedExactly() const override { return laz::consumedExactly(layer_); }
  bool overran() const override { return laz::overran(layer_); }
  void next(std::uint8_t* out, unsigned& context) override
  {
    auto [last, models] = bytes_.select(context);
    models->byte.resize(count_);
    for (std::size_t i = 0; i < count_; ++i) {
      if (layer_[i].present) {
        if (!models->byte[i])
          models->byte[i] = std::make_unique<SymbolModel>(256);
        (*last)[i] = static_cast<std::uint8_t>(
            (*last)[i] + layer_[i].dec.decodeSymbol(*models->byte[i]));
      }
      out[i] = (*last)[i];
    }
  }

 private:
  std::size_t count_;
  std::vector<Layer> layer_;
  ChannelPrediction<Bytes, Models> bytes_;
};

/// WAVEPACKET14: the waveform packet descriptor (index, offset, size, return point,
/// x y z of the direction), predicted from the previous one of its channel.
class WavePacket14V3 final : public LayeredItemDecoder {
  using Packet = std::array<std::uint8_t, 29>;
  struct Models {
    SymbolModel packet_index{256};
    std::array<SymbolModel, 4> offset_diff{SymbolModel(4), SymbolModel(4),
                                           SymbolModel(4), SymbolModel(4)};
    IntegerDecoder offset{32}, packet_size{32}, return_point{32}, xyz{32, 3};
    std::uint32_t last_offset_symbol = 0;
    std::int32_t last_diff = 0;
  };

 public:
  void first(const std::uint8_t* raw, unsigned& context) override
  {
    Packet p;
    std::memcpy(p.data(), raw, p.size());
    packets_.first(p, context);
  }
  std::size_t layers() const override { return 1; }
  void startLayers(const std::uint8_t* const* data, const std::uint32_t* sizes) override
  {
    layer_[0].start(data[0], sizes[0]);
  }
  bool consumedExactly() const override { return laz::consumedExactly(layer_); }
  bool overran() const override { return laz::overran(layer_); }

  void next(std::uint8_t* out, unsigned& context) override
  {
    if (!layer_[0].present) {
      std::memcpy(out, packets_.current().data(), 29);
      return;
    }
    auto [last, m] = packets_.select(context);
    ArithmeticDecoder& dec = layer_[0].dec;
    out[0] = static_cast<std::uint8_t>(dec.decodeSymbol(m->packet_index));
    const std::uint8_t* l = last->data() + 1;
    std::uint8_t* o = out + 1;
    m->last_offset_symbol = dec.decodeSymbol(m->offset_diff[m->last_offset_symbol]);
    const std::uint64_t last_offset = load<std::uint64_t>(l);
    std::uint64_t offset;
    switch (m->last_offset_symbol) {
    case 0: // the same packet
      offset = last_offset;
      break;
    case 1: // the next packet
      offset = last_offset + load<std::uint32_t>(l + 8);
      break;
    case 2:
      m->last_diff = m->offset.decode(dec, m->last_diff, 0);
      offset = last_offset +
               static_cast<std::uint64_t>(static_cast<std::int64_t>(m->last_diff));
      break;
    default: {
      const std::uint64_t low = dec.readInt();
      offset = (static_cast<std::uint64_t>(dec.readInt()) << 32) | low;
    }
    }
    store(o, offset);
    store(o + 8, m->packet_size.decode(dec, load<std::int32_t>(l + 8), 0));
    store(o + 12, m->return_point.decode(dec, load<std::int32_t>(l + 12), 0));
    for (int a = 0; a < 3; ++a)
      store(o + 16 + 4 * a, m->xyz.decode(dec, load<std::int32_t>(l + 16 + 4 * a),
                                          static_cast<unsigned>(a)));
    std::memcpy(last->data(), out, 29);
  }

 private:
  std::array<Layer, 1> layer_;
  ChannelPrediction<Packet, Models> packets_;
};

/// An item whose layers are counted but not decoded: its bytes stay as they were.
class SkippedItem final : public LayeredItemDecoder {
 public:
  explicit SkippedItem(std::size_t layers)
      : layers_(layers)
  {}
  void first(const std::uint8_t*, unsigned&) override {}
  std::size_t layers() const override { return layers_; }
  void startLayers(const std::uint8_t* const*, const std::uint32_t*) override {}
  void next(std::uint8_t*, unsigned&) override {}
  bool consumedExactly() const override { return true; }
  bool overran() const override { return false; }

 private:
  std::size_t layers_;
};

} // namespace

std::unique_ptr<LayeredItemDecoder> makeSkippedItem(std::size_t layers)
{
  return std::make_unique<SkippedItem>(layers);
}

std::unique_ptr<LayeredItemDecoder> makeWavePacket14V3()
{
  return std::make_unique<WavePacket14V3>();
}

std::unique_ptr<LayeredItemDecoder> makePoint14V3(bool position_only)
{
  return std::make_unique<Point14V3>(position_only);
}
std::unique_ptr<LayeredItemDecoder> makeRgb14V3(bool with_nir)
{
  return std::make_unique<Rgb14V3>(with_nir);
}
std::unique_ptr<LayeredItemDecoder> makeBytes14V3(std::size_t count)
{
  return std::make_unique<Bytes14V3>(count);
}

} // namespace laz
} // namespace pcl_vts
