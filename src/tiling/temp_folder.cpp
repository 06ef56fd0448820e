// Temporary folder with signal-safe cleanup (temp_folder.h).
#include "temp_folder.h"

#include <cerrno>
#include <csignal>
#include <cstring>
#include <dirent.h>
#include <fcntl.h>
#include <mutex>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>
#include <vector>

namespace pcl_vts {
namespace {

// One folder at a time per process (a job is sequential); the handler reads it.
constexpr std::size_t PATH_CAPACITY = 4096;
char g_folder[PATH_CAPACITY];
volatile std::sig_atomic_t g_active = 0;
std::mutex g_watch_mutex;
int g_watchers = 0;
struct sigaction g_previous[3];
constexpr int SIGNALS[3] = {SIGINT, SIGTERM, SIGHUP};

struct LinuxDirent64 {
  std::uint64_t ino;
  std::int64_t off;
  unsigned short reclen;
  unsigned char type;
  char name[1];
};

/// True when name starts with prefix (a loop: the signal handler calls it).
bool startsWith(const char* name, const char* prefix)
{
  for (; *prefix != 0; ++name, ++prefix)
    if (*name != *prefix)
      return false;
  return true;
}

/// True when name starts with one of `keep` (a list ended by nullptr).
bool keptName(const char* name, const char* const* keep)
{
  for (; *keep != nullptr; ++keep)
    if (startsWith(name, *keep))
      return true;
  return false;
}

/// Unlinks every entry of the folder whose name starts with none of `keep` (a list
/// ended by nullptr): open, getdents64 and unlinkat are async-signal-safe, so the
/// signal handler may call this.
void unlinkEntriesSignalSafe(const char* folder, const char* const* keep)
{
  const int fd = ::open(folder, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0)
    return;
  alignas(8) char buffer[8192];
  for (;;) {
    const long n = ::syscall(SYS_getdents64, fd, buffer, sizeof(buffer));
    if (n <= 0)
      break;
    for (long at = 0; at < n;) {
      const auto* entry = reinterpret_cast<const LinuxDirent64*>(buffer + at);
      const char* name = entry->name;
      if (!(name[0] == '.' && (name[1] == 0 || (name[1] == '.' && name[2] == 0))) &&
          !keptName(name, keep))
        ::unlinkat(fd, name, 0);
      at += entry->reclen;
    }
  }
  ::close(fd);
}

/// Unlinks every entry of the folder, then the folder (async-signal-safe).
void removeFolderSignalSafe(const char* folder)
{
  const char* const none[] = {nullptr};
  unlinkEntriesSignalSafe(folder, none);
  ::rmdir(folder);
}

void onSignal(int signal)
{
  if (g_active)
    removeFolderSignalSafe(g_folder);
  g_active = 0;
  for (int k = 0; k < 3; ++k)
    if (SIGNALS[k] == signal)
      ::sigaction(signal, &g_previous[k], nullptr);
  ::raise(signal);
}

} // namespace

Status TempFolder::create(const std::string& parent)
{
  remove();
  std::string pattern =
      (parent.empty() ? std::string(".") : parent) + "/.pcl_vts-XXXXXX";
  if (pattern.size() + 64 >= PATH_CAPACITY)
    return Status::error(StatusCode::IO_ERROR,
                         "temporary folder path too long: '" + parent + "'");
  std::vector<char> buffer(pattern.begin(), pattern.end());
  buffer.push_back('\0');
  if (::mkdtemp(buffer.data()) == nullptr)
    return Status::error(StatusCode::IO_ERROR, "cannot create a temporary folder in '" +
                                                   parent +
                                                   "': " + std::strerror(errno));
  path_ = buffer.data();
  owned_ = true;
  watchSignals(path_);
  return Status::success();
}

void TempFolder::adopt(const std::string& path)
{
  remove();
  if (path.empty() || path.size() + 64 >= PATH_CAPACITY)
    return;
  path_ = path;
  owned_ = false;
  watchSignals(path_);
}

void TempFolder::watchSignals(const std::string& path)
{
  // Several TempFolders may watch at once (MPI ranks as threads of a test, always
  // the same folder): the handler is installed by the first, restored by the last.
  const std::lock_guard<std::mutex> lock(g_watch_mutex);
  std::memcpy(g_folder, path.c_str(), path.size() + 1);
  if (g_watchers++ == 0) {
    struct sigaction action;
    std::memset(&action, 0, sizeof(action));
    action.sa_handler = onSignal;
    sigemptyset(&action.sa_mask);
    for (int k = 0; k < 3; ++k) {
      ::sigaction(SIGNALS[k], nullptr, &g_previous[k]);
      // A signal ignored on entry (nohup, a shell's background job) stays ignored.
      if (g_previous[k].sa_handler != SIG_IGN)
        ::sigaction(SIGNALS[k], &action, nullptr);
    }
  }
  g_active = 1;
}

void TempFolder::unwatchSignals()
{
  const std::lock_guard<std::mutex> lock(g_watch_mutex);
  if (--g_watchers == 0) {
    g_active = 0;
    for (int k = 0; k < 3; ++k)
      ::sigaction(SIGNALS[k], &g_previous[k], nullptr);
  }
}

std::uint64_t TempFolder::bytesUsed() const
{
  std::uint64_t bytes = 0;
  DIR* dir = path_.empty() ? nullptr : ::opendir(path_.c_str());
  if (dir == nullptr)
    return 0;
  while (const dirent* entry = ::readdir(dir)) {
    struct stat st {};
    if (::fstatat(::dirfd(dir), entry->d_name, &st, AT_SYMLINK_NOFOLLOW) == 0 &&
        S_ISREG(st.st_mode))
      bytes += static_cast<std::uint64_t>(st.st_blocks) * 512;
  }
  ::closedir(dir);
  return bytes;
}

void TempFolder::removeFilesExcept(std::initializer_list<const char*> keep) const
{
  std::vector<const char*> list(keep);
  list.push_back(nullptr);
  if (!path_.empty())
    unlinkEntriesSignalSafe(path_.c_str(), list.data());
}

void TempFolder::remove()
{
  if (path_.empty())
    return;
  unwatchSignals();
  if (owned_)
    removeFolderSignalSafe(path_.c_str());
  path_.clear();
  owned_ = false;
}

TempFolder::~TempFolder()
{
  remove();
}

} // namespace pcl_vts
