// A private folder for a job's temporary files, removed with everything in it when
// the job ends: on success, on error, and on SIGINT/SIGTERM/SIGHUP (the handler
// removes the files with async-signal-safe calls only, then re-raises the signal).
#pragma once
#include <pcl_vts/core/status.h>

#include <cstdint>
#include <initializer_list>
#include <string>

namespace pcl_vts {

class TempFolder {
 public:
  TempFolder() = default;
  ~TempFolder();
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;

  /// Creates "<parent>/.pcl_vts-XXXXXX"; IO_ERROR naming parent when it cannot.
  Status create(const std::string& parent);
  const std::string& path() const { return path_; }
  /// Disk the folder's files take now (allocated blocks), 0 when there is none.
  std::uint64_t bytesUsed() const;
  /// Unlinks every file of the folder whose name starts with none of `keep`.
  void removeFilesExcept(std::initializer_list<const char*> keep) const;
  /// Another process's folder (an MPI rank's view of rank 0's): removed by this
  /// process only if it receives SIGINT/SIGTERM/SIGHUP, so that a job stopped while
  /// rank 0 is busy or killed still leaves nothing behind; never by the destructor.
  void adopt(const std::string& path);
  /// Removes the folder and its files now (also done by the destructor), or, for an
  /// adopted folder, stops watching it.
  void remove();

 private:
  void watchSignals(const std::string& path);
  void unwatchSignals();
  std::string path_;
  bool owned_ = false;
};

} // namespace pcl_vts
