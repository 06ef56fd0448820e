// Little-endian fields of binary headers and records (LAS, its VLRs), read byte by
// byte so that alignment and the host's byte order never matter.
#pragma once
#include <cstdint>
#include <cstring>

namespace pcl_vts {

inline std::uint16_t u16(const std::uint8_t* p)
{
  return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}

inline std::uint32_t u32(const std::uint8_t* p)
{
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) |
         (static_cast<std::uint32_t>(p[3]) << 24);
}

inline std::uint64_t u64(const std::uint8_t* p)
{
  return static_cast<std::uint64_t>(u32(p)) |
         (static_cast<std::uint64_t>(u32(p + 4)) << 32);
}

inline std::int32_t i32(const std::uint8_t* p)
{
  const std::uint32_t u = u32(p);
  std::int32_t v;
  std::memcpy(&v, &u, 4);
  return v;
}

inline double f64(const std::uint8_t* p)
{
  const std::uint64_t u = u64(p);
  double v;
  std::memcpy(&v, &u, 8);
  return v;
}

} // namespace pcl_vts
