#include <pcl_vts/core/status.h>

#include <charconv>
#include <cmath>

namespace pcl_vts {

const char* statusCodeName(StatusCode code)
{
  switch (code) {
  case StatusCode::OK:
    return "OK";
  case StatusCode::EMPTY_INPUT:
    return "EMPTY_INPUT";
  case StatusCode::CAPACITY_EXCEEDED:
    return "CAPACITY_EXCEEDED";
  case StatusCode::TOO_FEW_POINTS:
    return "TOO_FEW_POINTS";
  case StatusCode::ALL_COLLINEAR:
    return "ALL_COLLINEAR";
  case StatusCode::COORDINATE_RANGE:
    return "COORDINATE_RANGE";
  case StatusCode::INVALID_PARAMETER:
    return "INVALID_PARAMETER";
  case StatusCode::IO_ERROR:
    return "IO_ERROR";
  case StatusCode::INTERNAL_ERROR:
    return "INTERNAL_ERROR";
  }
  return "UNKNOWN";
}

std::string formatValue(double value)
{
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

Status checkFiniteNonNegative(const char* name, double value, const char* note)
{
  if (std::isfinite(value) && value >= 0.0)
    return Status::success();
  return Status::error(StatusCode::INVALID_PARAMETER,
                       std::string(name) + " = " + formatValue(value) +
                           " must be finite and >= 0" + note);
}

std::string Status::toString() const
{
  if (ok())
    return "OK";
  return std::string(statusCodeName(code)) + ": " + message;
}

} // namespace pcl_vts
