// The inputs of one pcd_to_mesh run: files, folders (every file in them with a
// supported extension, by name) and @LIST files (one path per line, '#' comments,
// relative paths taken from the list's folder), meshed as one point set.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace pcl_vts {
namespace tools {

/// Expands the command-line inputs into files, in order. False with a message naming
/// the argument when a folder holds no supported file or a list cannot be read.
bool expandInputs(const std::vector<std::string>& arguments,
                  std::vector<std::string>& files, std::string& error);

/// Parses a size: a whole number of bytes or with a suffix K, M, G, T (powers of
/// 1024, any case, optional trailing B). False on anything else or zero.
bool parseByteSize(const std::string& text, std::uint64_t& bytes);

/// The machine's physical memory in bytes (0 if unknown).
std::uint64_t physicalMemoryBytes();

} // namespace tools
} // namespace pcl_vts
