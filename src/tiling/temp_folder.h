// A private folder for a job's temporary files, removed with everything in it when
// the job ends: on success, on error, and on SIGINT/SIGTERM/SIGHUP (the handler
// removes the files with async-signal-safe calls only, then re-raises the signal).
#pragma once
#include <pcl_vts/core/status.h>

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
  /// Removes the folder and its files now (also done by the destructor).
  void remove();

 private:
  std::string path_;
};

} // namespace pcl_vts
