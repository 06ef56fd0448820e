// libFuzzer harness for the PCD reader (pcd_cloud_reader.h): the bytes go to a memory
// file (memfd) read by path, as pcd_to_mesh does, through PCL's PCDReader for the
// body. Any bytes must give a status, never a crash or giant allocation. Built and
// run by tests/fuzz/run_fuzzers.sh when PCL's headers and libraries are found.
#include <pcl_vts/io/pcd_cloud_reader.h>

#include <pcl/console/print.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <sys/mman.h>
#include <unistd.h>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  static const bool quiet = [] {
    pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
    return true;
  }();
  (void)quiet;
  const int fd = ::memfd_create("fuzz.pcd", MFD_CLOEXEC);
  if (fd < 0)
    return 0;
  std::size_t written = 0;
  while (written < size) {
    const ssize_t n = ::write(fd, data + written, size - written);
    if (n <= 0)
      break;
    written += static_cast<std::size_t>(n);
  }
  std::vector<double> xyz;
  pcl_vts::PcdCloudInfo info;
  const std::string path = "/proc/self/fd/" + std::to_string(fd);
  const pcl_vts::Status s = pcl_vts::readPcdCloud(path, xyz, info);
  ::close(fd);
  if (s.ok() ? xyz.size() != 3 * info.points : !xyz.empty())
    __builtin_trap();
  return 0;
}
