// The one way pcl_vts writes a file: complete under its final name, or not at all.
// The bytes go to a temporary file in the same folder, which commit() flushes, syncs
// and renames over the name; an AtomicFile destroyed before commit() removes it. The
// mesh writer, the PNG writer and compare_methods' files all write through it.
#pragma once

#include <pcl_vts/core/export.h>
#include <pcl_vts/core/status.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace pcl_vts {

/// A file that appears under its final name only when commit() succeeds. Errors are
/// IO_ERROR messages naming the final path ("cannot write 'out.ply': File too
/// large"); a write error is kept and reported by commit(), so writers need not check
/// every call. Not copyable; one writer at a time.
class PCL_VTS_CORE_EXPORT AtomicFile {
 public:
  explicit AtomicFile(std::string path);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  /// Removes the temporary file unless commit() succeeded.
  ~AtomicFile();

  /// Creates ".<name>.tmp.<pid>" (then ".1", ".2", ... if taken) beside path.
  /// \return IO_ERROR "cannot write 'p': folder 'f/' does not exist", or naming why
  ///         the folder refused the temporary file.
  Status open();

  /// Appends n bytes (buffered); after an error, does nothing.
  void write(const void* data, std::size_t n);
  void write(std::string_view text) { write(text.data(), text.size()); }

  /// True while no write has failed.
  bool good() const { return error_ == 0; }

  /// Flushes, syncs, closes and renames the temporary file over path, then syncs
  /// the folder (best effort). \return the first error of any step.
  Status commit();

  /// Bytes written to the file so far.
  std::uint64_t bytes() const { return bytes_; }

 private:
  Status failure(const std::string& what, int err);
  void discard();
  bool flushBuffer();
  void writeAll(const char* data, std::size_t n);
  void syncFolder() const;

  std::string path_;
  std::string temp_path_;
  int fd_ = -1;
  int error_ = 0;
  std::vector<char> buffer_;
  std::uint64_t bytes_ = 0;
};

/// Writes n bytes to path through an AtomicFile. \return its error, if any.
PCL_VTS_CORE_EXPORT Status writeFileAtomically(const std::string& path,
                                               const void* data, std::size_t n);

} // namespace pcl_vts
