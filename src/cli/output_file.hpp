#pragma once
// Where the CLI writes: never over what the user has. An output goes to a regular file (or
// "-", standard output) that is not one of the run's inputs, through a temporary file
// beside it that is synced and renamed into place only when the whole output is written.
// An interrupted run (SIGINT, SIGTERM) removes its temporary files; one killed outright
// leaves them named with its process id, and the next run writing there removes them.
#include <cstddef>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace ccomp::cli {

/// A file a run reads, and what it is to the user ("the machine model").
struct RunInput {
  std::string role, path;
};

/// Refuses (ccomp::Error, usage) an output path that is a symbolic link, a device, a FIFO,
/// a folder or anything but a regular file, or that is the same file as one of `inputs`
/// (the program, the model, the tool table, the measurements); `what` names the option.
void check_output(const std::string& path, const std::vector<RunInput>& inputs, const std::string& what);

/// Refuses (usage) two targets that would write the same file.
void check_distinct_outputs(const std::vector<std::string>& outputs);

/// The stdio buffer an output is written through. (glibc takes setvbuf's size only with a
/// buffer of the caller's: without one it allocates its own, BUFSIZ or the file system's
/// block if smaller, 4 kB here: a write call each.)
inline constexpr std::size_t kOutputBuffer = std::size_t{1} << 18;

/// Gives standard output a buffer of kOutputBuffer bytes; call it before anything is
/// written there (later calls do nothing).
void buffer_standard_output();

/// An output being written: `file()` is a temporary file beside `path`; `commit()` flushes,
/// syncs and renames it into place; destroyed without a commit it is removed.
class OutputFile {
 public:
  /// Throws ccomp::Error (io) when the temporary file cannot be made, or `path` exists and is
  /// read-only. The file gets `mode` (permission bits), else the mode of the file it
  /// replaces, else 0666 less the umask.
  explicit OutputFile(std::string path, std::optional<unsigned> mode = {});
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  ~OutputFile();

  [[nodiscard]] std::FILE* file() const { return file_; }
  [[nodiscard]] const std::string& temporary() const { return temporary_; }
  /// Throws ccomp::Error (io, exit 6) on any write, sync or rename failure.
  void commit();
  /// Flushes, syncs and closes the temporary (throws io on failure); link_as() then gives
  /// it a name that does not exist yet: false when `path` exists. The temporary itself is
  /// removed on destruction, the linked name stays.
  void finish();
  [[nodiscard]] bool link_as(const std::string& path);

 private:
  void remove_temporary();
  std::string path_, temporary_;
  std::unique_ptr<char[]> buffer_;  ///< file_'s stdio buffer (freed after the destructor closes file_)
  std::FILE* file_ = nullptr;
};

/// `text` into `path` ("-": standard output) through an OutputFile.
void write_output(const std::string& path, const std::string& text);

/// Standard output flushed; throws ccomp::Error (io) if anything written to it was lost
/// (a full disk, a closed pipe).
void finish_standard_output();

/// Takes SIGINT/SIGTERM/SIGHUP on a thread of its own that removes the temporary files being
/// written and ends the process by the signal (not a signal the caller ignores; a handler
/// where that thread cannot be had; call it before any other thread is made), ignores SIGPIPE and SIGXFSZ (a closed
/// pipe, a file past `ulimit -f`: then a write error, exit 6) and reads the umask the outputs' modes follow. Call it first.
void remove_temporaries_on_interrupt();

}  // namespace ccomp::cli
