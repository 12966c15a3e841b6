#include "output_file.hpp"

#include <fcntl.h>
#include <pthread.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <set>
#include <system_error>
#include <thread>
#include <vector>

#include "ccomp/error.hpp"

namespace ccomp::cli {
namespace fs = std::filesystem;
namespace {

/// The temporary files being written. A signal is taken on a thread of its own (sigwait),
/// which holds the lock while it removes them and ends the process: no thread makes one
/// meanwhile, however many run (a `-j 1100` batch left up to 81 behind: more outputs than
/// the handler's table held, and files made while the handler ran). The lock and the list
/// are never destroyed: a signal may come while the process exits.
std::mutex& registry_lock() {
  static auto* lock = new std::mutex;
  return *lock;
}
std::vector<const char*>& registry() {
  static auto* names = new std::vector<const char*>;
  return *names;
}

/// The same names for a handler run on a signal, where the thread above could not be had:
/// it may only read what is already there and call unlink(), so they are fixed pointers in
/// a fixed table (more outputs at once than slots: the next run's clean-up, by process id,
/// takes those).
constexpr std::size_t kSlots = 1024;
std::array<std::atomic<const char*>, kSlots> g_temporaries{};

/// (Under the registry's lock.)
void hold(const char* path) {
  registry().push_back(path);
  for (auto& slot : g_temporaries) {
    const char* empty = nullptr;
    if (slot.compare_exchange_strong(empty, path)) return;
  }
}

/// (Under the registry's lock.)
void release(const char* path) {
  std::erase(registry(), path);
  for (auto& slot : g_temporaries) {
    const char* mine = path;
    if (slot.compare_exchange_strong(mine, nullptr)) return;
  }
}

extern "C" void remove_temporaries_and_stop(int signal) {
  for (auto& slot : g_temporaries)
    if (const char* path = slot.load()) ::unlink(path);
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

/// The signal thread: waits for one of `signals`, removes every temporary and ends the
/// process by that signal (exit 128+N, as the shell reports it), the lock held to the end.
void watch_signals(sigset_t signals) {
  int signal = 0;
  while (::sigwait(&signals, &signal) != 0) {
  }
  registry_lock().lock();  // never unlocked: no temporary is made or released after this
  for (const char* path : registry()) ::unlink(path);
  std::signal(signal, SIG_DFL);
  sigset_t one;
  sigemptyset(&one);
  sigaddset(&one, signal);
  ::pthread_sigmask(SIG_UNBLOCK, &one, nullptr);
  std::raise(signal);
  ::_exit(128 + signal);  // (not reached: the signal's default action ends the process)
}

/// "<output>.ccomp-": what the temporary files for `output` start with, "<pid>-XXXXXX"
/// following. A long name is cut so that the whole fits NAME_MAX (255 bytes): an output
/// named up to the limit can be written.
std::string temporary_prefix(const fs::path& output) {
  constexpr std::size_t kNameMax = 255, kTail = 7 + 10 + 1 + 6;  // ".ccomp-", pid, '-', XXXXXX
  return output.filename().string().substr(0, kNameMax - kTail) + ".ccomp-";
}

/// Removes temporary files beside `output` that a process no longer running left (a run
/// killed outright: SIGKILL, a power cut).
void remove_orphans(const fs::path& output) {
  const fs::path folder = output.parent_path().empty() ? fs::path(".") : output.parent_path();
  const std::string prefix = temporary_prefix(output);
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(folder, ec)) {
    const std::string name = e.path().filename().string();
    if (!name.starts_with(prefix)) continue;
    const std::string rest = name.substr(prefix.size());
    const auto dash = rest.find('-');
    if (dash == std::string::npos || dash == 0) continue;
    char* end = nullptr;
    const long pid = std::strtol(rest.c_str(), &end, 10);
    if (end != rest.c_str() + dash || pid <= 0) continue;
    if (::kill(static_cast<pid_t>(pid), 0) == -1 && errno == ESRCH) fs::remove(e.path(), ec);
  }
}

/// Whether `path` names the file standard input reads (`ccomp - -o p.ngc < p.ngc`): the
/// same device and inode.
bool is_standard_input(const std::string& path) {
  struct stat in {}, out {};
  return ::fstat(STDIN_FILENO, &in) == 0 && ::stat(path.c_str(), &out) == 0 && in.st_dev == out.st_dev &&
         in.st_ino == out.st_ino;
}

/// Refuses (io, exit 6) to replace a file the user could not write: the rename would replace
/// it all the same, as the folder is writable. Root may write anything, so a file with no
/// write bit at all (0444, chmod a-w) is refused for root too: someone protected it.
void check_writable(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return;
  if (::access(path.c_str(), W_OK) != 0 || (st.st_mode & 0222) == 0)
    throw Error(ErrorKind::io, fmt::format("cannot replace '{}': it is read-only (mode {:04o}); make it writable "
                                           "or write elsewhere",
                                           path, st.st_mode & 07777));
}

}  // namespace

void check_output(const std::string& path, const std::vector<RunInput>& inputs, const std::string& what) {
  if (path == "-") return;
  struct stat st {};
  if (::lstat(path.c_str(), &st) == 0) {
    if (S_ISLNK(st.st_mode)) {
      std::error_code ec;
      throw Error(ErrorKind::usage,
                  fmt::format("{} '{}' is a symbolic link (to '{}'): name the file itself, or remove the link", what,
                              path, fs::read_symlink(path, ec).string()));
    }
    if (!S_ISREG(st.st_mode))
      throw Error(ErrorKind::usage,
                  fmt::format("{} '{}' is not a regular file (a folder, a device or a FIFO): ccomp writes files, or "
                              "standard output with '-'",
                              what, path));
  }
  for (const RunInput& input : inputs) {
    if (input.path.empty()) continue;
    std::error_code ec;
    if (input.path == "-" ? is_standard_input(path) : fs::equivalent(path, input.path, ec))
      throw Error(ErrorKind::usage,
                  fmt::format("{} '{}' is {} '{}', which this run reads: it would be lost; write "
                              "elsewhere{}",
                              what, path, input.role, input.path,
                              input.role == "the program" ? " (or use --in-place, which keeps a backup)" : ""));
  }
  check_writable(path);
}

void check_distinct_outputs(const std::vector<std::string>& outputs) {
  std::set<std::string> seen;
  for (const std::string& o : outputs) {
    if (o == "-") continue;
    std::error_code ec;
    const fs::path key = fs::weakly_canonical(o, ec);
    if (!seen.insert(ec ? o : key.string()).second)
      throw Error(ErrorKind::usage,
                  fmt::format("two outputs would both be written to '{}': one would be lost (rename an input, or "
                              "write them to different folders)",
                              o));
  }
}

namespace {

/// The process' umask, read once at start-up (reading it means setting it).
mode_t g_umask = 022;

/// The mode the output gets: the file's it replaces, else what a plain open() would give.
mode_t output_mode(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) return st.st_mode & 07777;
  return 0666 & ~g_umask;
}

}  // namespace

// (The buffer first: its allocation failing once the temporary exists would leave it.)
OutputFile::OutputFile(std::string path, std::optional<unsigned> mode)
    : path_(std::move(path)), buffer_(std::make_unique_for_overwrite<char[]>(kOutputBuffer)) {
  const fs::path out(path_);
  remove_orphans(out);
  temporary_ = ((out.parent_path().empty() ? fs::path(".") : out.parent_path()) /
                (temporary_prefix(out) + std::to_string(::getpid()) + "-XXXXXX"))
                   .string();
  // Made and held under the lock: the signal thread sees it, or it is not made. (Held for a
  // handler before it exists: one that comes while mkstemp makes it removes it too.)
  int fd = -1, made = 0;
  {
    const std::lock_guard lock(registry_lock());
    hold(temporary_.c_str());
    fd = ::mkstemp(temporary_.data());
    made = errno;
    if (fd < 0) release(temporary_.c_str());
  }
  if (fd < 0)
    throw Error(ErrorKind::io,
                fmt::format("cannot create a temporary file beside '{}': {}", path_, std::strerror(made)));
  (void)::fchmod(fd, mode ? static_cast<mode_t>(*mode) : output_mode(path_));  // mkstemp makes 0600
  file_ = ::fdopen(fd, "wb");
  if (!file_) {
    ::close(fd);
    remove_temporary();
    throw Error(ErrorKind::io, fmt::format("cannot write '{}'", path_));
  }
  std::setvbuf(file_, buffer_.get(), _IOFBF, kOutputBuffer);
}

OutputFile::~OutputFile() {
  if (file_) std::fclose(file_);
  if (!temporary_.empty()) remove_temporary();
}

void OutputFile::remove_temporary() {
  const std::lock_guard lock(registry_lock());
  ::unlink(temporary_.c_str());
  release(temporary_.c_str());
}

void OutputFile::commit() {
  finish();
  check_writable(path_);  // again: it may have been made read-only meanwhile
  if (std::rename(temporary_.c_str(), path_.c_str()) != 0)
    throw Error(ErrorKind::io,
                fmt::format("cannot move the result into place as '{}': {}", path_, std::strerror(errno)));
  {
    const std::lock_guard lock(registry_lock());
    release(temporary_.c_str());
  }
  temporary_.clear();
  // The rename itself survives a power cut once the folder is synced.
  const fs::path folder = fs::path(path_).parent_path().empty() ? fs::path(".") : fs::path(path_).parent_path();
  if (const int dir = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY); dir >= 0) {
    (void)::fsync(dir);
    ::close(dir);
  }
}

void OutputFile::finish() {
  const bool written = std::fflush(file_) == 0 && !std::ferror(file_) && ::fsync(::fileno(file_)) == 0;
  const int error = errno;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!written || !closed)
    throw Error(ErrorKind::io, fmt::format("cannot write '{}': {}", path_, std::strerror(written ? errno : error)));
}

bool OutputFile::link_as(const std::string& path) {
  // link() never replaces: a file of that name, even one appearing meanwhile, is kept.
  if (::link(temporary_.c_str(), path.c_str()) == 0) return true;
  if (errno == EEXIST) return false;
  throw Error(ErrorKind::io, fmt::format("cannot write '{}': {}", path, std::strerror(errno)));
}

void write_output(const std::string& path, const std::string& text) {
  if (path == "-") {
    std::fwrite(text.data(), 1, text.size(), stdout);
    return;
  }
  OutputFile out(path);
  std::fwrite(text.data(), 1, text.size(), out.file());
  out.commit();
}

void buffer_standard_output() {
  // Static, without a destructor: standard output is flushed at exit, after the destructors.
  alignas(64) static char buffer[kOutputBuffer];
  static bool given = false;
  if (given) return;
  given = true;
  std::setvbuf(stdout, buffer, _IOFBF, sizeof buffer);
}

void finish_standard_output() {
  errno = 0;
  if (std::fflush(stdout) != 0 || std::ferror(stdout))
    throw Error(ErrorKind::io, fmt::format("cannot write standard output{}",
                                           errno ? fmt::format(": {}", std::strerror(errno)) : std::string()));
}

void remove_temporaries_on_interrupt() {
  g_umask = ::umask(0);
  ::umask(g_umask);
  sigset_t taken;
  sigemptyset(&taken);
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction old {};
    // A signal the caller ignores (nohup, a background job) stays ignored.
    if (::sigaction(signal, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
    sigaddset(&taken, signal);
  }
  // Blocked here, before any other thread is made (they inherit the mask), and taken by the
  // signal thread alone; without that thread, by a handler on whichever thread it comes to.
  sigset_t before;
  ::pthread_sigmask(SIG_BLOCK, &taken, &before);
  try {
    std::thread(watch_signals, taken).detach();
  } catch (const std::system_error&) {
    ::pthread_sigmask(SIG_SETMASK, &before, nullptr);
    for (const int signal : {SIGINT, SIGTERM, SIGHUP})
      if (sigismember(&taken, signal) == 1) std::signal(signal, remove_temporaries_and_stop);
  }
  // A closed pipe is a write error (exit 6), not a silent death by SIGPIPE; so is a file
  // past `ulimit -f` (EFBIG), which would otherwise end the run by SIGXFSZ and leave the
  // temporary behind.
  std::signal(SIGPIPE, SIG_IGN);
  std::signal(SIGXFSZ, SIG_IGN);
}

}  // namespace ccomp::cli
