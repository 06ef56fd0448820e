// One decoder per LASzip item (a field group of the point record: POINT10, GPSTIME11,
// RGB12, BYTE, POINT14, ...). A chunk's first record is stored raw; every later record
// is predicted from the previous ones of its chunk, so an item decoder carries the
// state between records and is made afresh for each chunk.
#pragma once

#include "arithmetic_decoder.h"

#include <cstddef>
#include <cstdint>
#include <memory>

namespace pcl_vts {
namespace laz {

/// Items of the pointwise schemes (compressor 1 and 2): all share one stream.
class PointwiseItemDecoder {
 public:
  virtual ~PointwiseItemDecoder() = default;
  /// The chunk's first record, raw: becomes the prediction state.
  virtual void first(const std::uint8_t* raw) = 0;
  /// Decodes the next record's bytes of this item into out.
  virtual void next(ArithmeticDecoder& dec, std::uint8_t* out) = 0;
};

/// Version 1 items (LASzip 1.x, compressor 1).
std::unique_ptr<PointwiseItemDecoder> makePoint10V1();
std::unique_ptr<PointwiseItemDecoder> makeGpsTime11V1();
std::unique_ptr<PointwiseItemDecoder> makeRgb12V1();
std::unique_ptr<PointwiseItemDecoder> makeBytesV1(std::size_t count);

/// Version 2 items (LASzip 2.x, compressor 2): the usual pointwise-chunked files.
std::unique_ptr<PointwiseItemDecoder> makePoint10V2();
std::unique_ptr<PointwiseItemDecoder> makeGpsTime11V2();
std::unique_ptr<PointwiseItemDecoder> makeRgb12V2();
std::unique_ptr<PointwiseItemDecoder> makeBytesV2(std::size_t count);

/// Items of the layered scheme (compressor 3, LAS 1.4 point formats 6-10): each
/// field group has its own stream ("layer") in the chunk, so a reader can skip them.
class LayeredItemDecoder {
 public:
  virtual ~LayeredItemDecoder() = default;
  /// The chunk's first record, raw; context: the scanner channel of POINT14 (the
  /// other items follow it).
  virtual void first(const std::uint8_t* raw, unsigned& context) = 0;
  /// How many layers this item has (their byte counts follow the point count).
  virtual std::size_t layers() const = 0;
  /// Starts the layer streams: sizes[i] bytes at data[i].
  virtual void startLayers(const std::uint8_t* const* data,
                           const std::uint32_t* sizes) = 0;
  virtual void next(std::uint8_t* out, unsigned& context) = 0;
  /// True when every layer decoded to its last byte, not short of it nor beyond:
  /// the encoder pads its streams so, and anything else means corrupt bytes.
  virtual bool consumedExactly() const = 0;
  /// True once a layer was read beyond its end: the chunk is corrupt, stop early.
  virtual bool overran() const = 0;
};

/// position_only: x, y, z, returns and class only (the layers of the other fields
/// are not decoded, their bytes in the record are the chunk's first values).
std::unique_ptr<LayeredItemDecoder> makePoint14V3(bool position_only = false);
std::unique_ptr<LayeredItemDecoder> makeRgb14V3(bool with_nir);
std::unique_ptr<LayeredItemDecoder> makeBytes14V3(std::size_t count);
std::unique_ptr<LayeredItemDecoder> makeWavePacket14V3();
/// An item read past: `layers` layers counted, nothing decoded.
std::unique_ptr<LayeredItemDecoder> makeSkippedItem(std::size_t layers);

} // namespace laz
} // namespace pcl_vts
