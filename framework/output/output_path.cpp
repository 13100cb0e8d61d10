#include "output/output_path.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <limits.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>

namespace gdsmc::host {

namespace fs = std::filesystem;

namespace {

std::string quote_path(const fs::path& p) { return "'" + p.string() + "'"; }

const char* kind_of(mode_t m) {
  if (S_ISDIR(m)) return "a directory";
  if (S_ISCHR(m)) return "a character device";
  if (S_ISBLK(m)) return "a block device";
  if (S_ISFIFO(m)) return "a named pipe";
  if (S_ISSOCK(m)) return "a socket";
  return "not a regular file";
}

// What may be replaced: nothing, a regular file, or a symbolic link (the link itself).
void check_replaceable(const fs::path& file) {
  struct stat st;
  if (::lstat(file.c_str(), &st) != 0) {
    if (errno == ENOENT) return;
    throw OutputPathError("cannot examine " + quote_path(file) + ": " + std::strerror(errno));
  }
  if (S_ISREG(st.st_mode) || S_ISLNK(st.st_mode)) return;
  if (S_ISDIR(st.st_mode))
    throw OutputPathError(quote_path(file) + " is a directory; give a file name, e.g. " + quote_path(file / "NAME.h5"));
  throw OutputPathError(quote_path(file) + " is " + kind_of(st.st_mode) +
                        "; gdsmc writes its output only to a new name or over a regular file (or a symbolic link)");
}

// This process as a temporary name records it: "HOST-NS-PID" (NS: the PID namespace's inode,
// 0 when unknown), so that a later run can tell whether the writer still exists.
struct Creator {
  std::string host, ns, pid;
};

Creator this_creator() {
  Creator w;
  char buf[256] = {};
  if (::gethostname(buf, sizeof buf - 1) != 0 || !buf[0]) std::strcpy(buf, "unknown");
  for (char* c = buf; *c; ++c)
    if (*c == '/' || static_cast<unsigned char>(*c) <= ' ') *c = '_';
  w.host = std::string(buf).substr(0, 64);
  char link[128] = {};
  const ssize_t n = ::readlink("/proc/self/ns/pid", link, sizeof link - 1);  // "pid:[4026531836]"
  for (ssize_t k = 0; k < std::max<ssize_t>(n, 0); ++k)
    if (link[k] >= '0' && link[k] <= '9') w.ns += link[k];
  if (w.ns.empty()) w.ns = "0";
  w.pid = std::to_string(::getpid());
  return w;
}

bool all_digits(const std::string& s) {
  if (s.empty() || s.size() > 19) return false;
  for (char c : s)
    if (c < '0' || c > '9') return false;
  return true;
}

}  // namespace

std::string OutputTarget::replacement_notice(bool run) const {
  const std::string f = file.string();
  switch (existing) {
    case Existing::none: return "";
    case Existing::regular_file:
      return run ? "replacing existing " + f + " when the run completes" : f + " exists: a run would replace it";
    case Existing::symlink:
      return f + " is a symbolic link to " + link_target.string() +
             (run ? ": the run replaces the link (not " : ": a run would replace the link (not ") +
             link_target.string() + ") with its output";
  }
  return "";
}

std::string temporary_prefix(const fs::path& file) {
  return "." + file.filename().string().substr(0, 100) + ".gdsmc-partial-";
}

void check_checkpoint_directory(const OutputTarget& target, const fs::path& directory, const std::string& longest_file) {
  const std::string name = directory.filename().string();
  const long name_max = ::pathconf(target.directory.c_str(), _PC_NAME_MAX);
  if (name_max > 0 && name.size() > static_cast<std::size_t>(name_max))
    throw OutputPathError("the checkpoint directory this run creates (run.checkpoint), " +
                          quote_path(name.substr(0, 40) + "...") + ", is " + std::to_string(name.size()) +
                          " bytes long; the filesystem of " + quote_path(target.directory) + " allows at most " +
                          std::to_string(name_max) + ": give the output a name of at most " +
                          std::to_string(name_max - (name.size() - target.file.filename().string().size())) + " bytes");
  const std::size_t length = (fs::absolute(directory) / longest_file).string().size();
  if (length >= PATH_MAX)
    throw OutputPathError("the files of the checkpoint directory this run creates (run.checkpoint), " +
                          quote_path(directory.string().substr(0, 40) + "...") + ", have paths of " +
                          std::to_string(length) + " bytes; at most " + std::to_string(PATH_MAX - 1) + " are allowed");
  struct stat st;
  if (::stat(directory.c_str(), &st) == 0 && !S_ISDIR(st.st_mode))
    throw OutputPathError(quote_path(directory) + ", where this run keeps its checkpoint (run.checkpoint), exists and "
                          "is not a directory: remove it or give another output name");
}

OutputTarget check_output_path(const fs::path& file, const std::vector<RunInput>& inputs) {
  const std::string s = file.string();
  if (s.empty()) throw OutputPathError("the file name is empty; give a file name such as NAME.h5");
  const std::string name = file.filename().string();
  if (name.empty() || name == "." || name == "..")
    throw OutputPathError(quote_path(file) + " names a directory; give a file name, e.g. " +
                          quote_path(file / "NAME.h5"));
  OutputTarget t;
  t.file = file;
  t.directory = file.has_parent_path() ? file.parent_path() : fs::path(".");
  struct stat ds;
  if (::stat(t.directory.c_str(), &ds) != 0) {
    if (errno == ENOENT) throw OutputPathError("the directory " + quote_path(t.directory) + " does not exist");
    if (errno == ENOTDIR) throw OutputPathError(quote_path(t.directory) + " is not a directory");
    throw OutputPathError("cannot examine the directory " + quote_path(t.directory) + ": " + std::strerror(errno));
  }
  if (!S_ISDIR(ds.st_mode)) throw OutputPathError(quote_path(t.directory) + " is not a directory");
  const long name_max = ::pathconf(t.directory.c_str(), _PC_NAME_MAX);
  if (name_max > 0 && name.size() > static_cast<std::size_t>(name_max))
    throw OutputPathError("the file name " + quote_path(name.substr(0, 40) + "...") + " is " + std::to_string(name.size()) +
                          " bytes long; the filesystem of " + quote_path(t.directory) + " allows at most " +
                          std::to_string(name_max));
  const std::size_t length = fs::absolute(file).string().size();
  if (length >= PATH_MAX)
    throw OutputPathError("the path " + quote_path(s.substr(0, 40) + "...") + " is " + std::to_string(length) +
                          " bytes long; at most " + std::to_string(PATH_MAX - 1) + " are allowed");
  check_replaceable(file);
  struct stat st;
  if (::lstat(file.c_str(), &st) == 0) {
    if (S_ISLNK(st.st_mode)) {
      t.existing = OutputTarget::Existing::symlink;
      std::error_code ec;
      t.link_target = fs::read_symlink(file, ec);
    } else {
      t.existing = OutputTarget::Existing::regular_file;
    }
  }
  // Never write over (or through a link to) what the run reads.
  for (const auto& in : inputs) {
    std::error_code ec;
    if (t.existing != OutputTarget::Existing::none && fs::equivalent(file, in.file, ec))
      throw OutputPathError(quote_path(file) + (t.existing == OutputTarget::Existing::symlink ? " links to " : " is ") +
                            in.what + " (" + quote_path(in.file) + "), which this run reads; choose another output name");
  }
  return t;
}

namespace {
// The live temporaries, for a handler that must _exit without unwinding: a path is written
// while its slot is not yet published, and the handler reads only published slots.
struct LiveTemporary {
  std::atomic<bool> published{false};
  char path[PATH_MAX + 1] = {};
  dev_t dev = 0;
  ino_t ino = 0;
};
constexpr int kLiveSlots = 8;
LiveTemporary g_live[kLiveSlots];
std::atomic<bool> g_live_claimed[kLiveSlots];

int publish_live(const std::string& path, dev_t dev, ino_t ino) {
  if (path.size() > PATH_MAX) return -1;
  for (int i = 0; i < kLiveSlots; ++i) {
    if (g_live_claimed[i].exchange(true)) continue;
    std::memcpy(g_live[i].path, path.c_str(), path.size() + 1);
    g_live[i].dev = dev;
    g_live[i].ino = ino;
    g_live[i].published.store(true);
    return i;
  }
  return -1;  // more than kLiveSlots at once: the destructor still removes it on a normal exit
}

void withdraw_live(int slot) {
  if (slot < 0) return;
  g_live[slot].published.store(false);
  g_live_claimed[slot].store(false);
}
}  // namespace

void remove_live_temporaries_from_signal_handler() noexcept {
  for (auto& t : g_live) {
    if (!t.published.load()) continue;
    struct stat st;
    if (::lstat(t.path, &st) == 0 && st.st_dev == t.dev && st.st_ino == t.ino) ::unlink(t.path);
  }
}

TemporaryFile::TemporaryFile(const OutputTarget& target) {
  const Creator w = this_creator();
  const std::string tmpl =
      (target.directory / (temporary_prefix(target.file) + w.host + "-" + w.ns + "-" + w.pid + "-XXXXXX")).string();
  std::vector<char> buf(tmpl.begin(), tmpl.end());
  buf.push_back('\0');
  fd_ = ::mkostemp(buf.data(), O_CLOEXEC);  // O_EXCL: never opens a file that exists
  if (fd_ < 0)
    throw OutputPathError("cannot create a file in " + quote_path(target.directory) + ": " + std::strerror(errno));
  path_ = buf.data();
  struct stat st;
  ::fstat(fd_, &st);
  dev_ = st.st_dev;
  ino_ = st.st_ino;
  live_slot_ = publish_live(path_.string(), dev_, ino_);
  // mkstemp creates 0600; the output gets the permissions any new file would.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ::fchmod(fd_, 0666 & ~mask);
}

TemporaryFile::~TemporaryFile() { remove(); }

bool TemporaryFile::is(int other_fd) const {
  struct stat st;
  return ::fstat(other_fd, &st) == 0 && st.st_dev == dev_ && st.st_ino == ino_;
}

void TemporaryFile::remove() {
  if (fd_ < 0) return;
  withdraw_live(live_slot_);
  live_slot_ = -1;
  struct stat st;
  if (::lstat(path_.c_str(), &st) == 0 && st.st_dev == dev_ && st.st_ino == ino_) ::unlink(path_.c_str());
  ::close(fd_);
  fd_ = -1;
}

void TemporaryFile::rename_over(const OutputTarget& target) {
  if (::fsync(fd_) != 0)
    throw OutputPathError("cannot write " + quote_path(path_) + " to disk: " + std::strerror(errno));
  struct stat st;
  if (::lstat(path_.c_str(), &st) != 0 || st.st_dev != dev_ || st.st_ino != ino_)
    throw OutputPathError("the temporary file " + quote_path(path_) + " was removed or replaced during the run");
  check_replaceable(target.file);  // what is there may have changed since the run began
  if (::rename(path_.c_str(), target.file.c_str()) != 0)
    throw OutputPathError("cannot rename " + quote_path(path_) + " to " + quote_path(target.file) + ": " +
                          std::strerror(errno));
  withdraw_live(live_slot_);  // the name is the output's now: a later signal must not remove it
  live_slot_ = -1;
  ::close(fd_);
  fd_ = -1;
  // The rename itself on disk (best effort: not every filesystem syncs directories).
  const int dir = ::open(target.directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {
    ::fsync(dir);
    ::close(dir);
  }
}

void probe_temporary(const OutputTarget& target) { TemporaryFile probe(target); }

fs::path output_lock_path(const fs::path& file) {
  const fs::path directory = file.has_parent_path() ? file.parent_path() : fs::path(".");
  return directory / ("." + file.filename().string().substr(0, 100) + ".gdsmc-lock");
}

namespace {
// Whether `fd` (locked) is still the file at `path`: a run that ended may have removed the name
// between our open and our flock, and a lock on a removed file guards nothing.
bool still_named(int fd, const fs::path& path, dev_t& dev, ino_t& ino) {
  struct stat held, named;
  if (::fstat(fd, &held) != 0 || ::lstat(path.c_str(), &named) != 0) return false;
  dev = held.st_dev;
  ino = held.st_ino;
  return held.st_dev == named.st_dev && held.st_ino == named.st_ino;
}
}  // namespace

OutputLock::OutputLock(const OutputTarget& target) : path_(output_lock_path(target.file)) {
  for (int attempt = 0; attempt < 16; ++attempt) {
    // A directory where no file can be created is refused by the temporary file's creation, with
    // its own message: the run then goes on to that without a lock.
    const int fd = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0666);
    if (fd < 0) return;
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int error = errno;
      if (error != EWOULDBLOCK) {  // no locks on this file system: go on without one
        ::close(fd);
        return;
      }
      char holder[512] = {};
      const ssize_t n = ::pread(fd, holder, sizeof holder - 1, 0);
      ::close(fd);
      std::string who = n > 0 ? std::string(holder, static_cast<std::size_t>(n)) : std::string();
      while (!who.empty() && (who.back() == '\n' || who.back() == ' ')) who.pop_back();
      throw OutputPathError("another gdsmc run is writing " + quote_path(target.file) + " now" +
                            (who.empty() ? "" : " (" + who + ")") +
                            ": two runs cannot write one output; wait until it ends, or give this run another "
                            "output name (-o FILE)");
    }
    dev_t dev = 0;
    ino_t ino = 0;
    if (!still_named(fd, path_, dev, ino)) {
      ::close(fd);
      continue;
    }
    const Creator w = this_creator();
    const std::string who = "gdsmc process " + w.pid + " on host " + w.host + "\n";
    if (::ftruncate(fd, 0) == 0) (void)!::pwrite(fd, who.data(), who.size(), 0);
    fd_ = fd;
    live_slot_ = publish_live(path_.string(), dev, ino);
    return;
  }
  throw OutputPathError("cannot lock " + quote_path(path_) + ": it keeps being replaced");
}

OutputLock::~OutputLock() {
  if (fd_ < 0) return;
  withdraw_live(live_slot_);
  dev_t dev = 0;
  ino_t ino = 0;
  if (still_named(fd_, path_, dev, ino)) ::unlink(path_.c_str());  // while it is still held
  ::close(fd_);
}

std::vector<std::string> remove_stale_temporaries(const OutputTarget& target) {
  std::vector<std::string> removed;
  const Creator me = this_creator();
  if (me.ns == "0") return removed;  // without the PID namespace no PID can be proved dead
  // An output lock no live process holds (its run was killed): removed while this process holds
  // it, so that no run that takes it meanwhile loses it.
  const fs::path lock = output_lock_path(target.file);
  const int lock_fd = ::open(lock.c_str(), O_RDWR | O_CLOEXEC | O_NOFOLLOW);
  if (lock_fd >= 0) {
    dev_t dev = 0;
    ino_t ino = 0;
    if (::flock(lock_fd, LOCK_EX | LOCK_NB) == 0 && still_named(lock_fd, lock, dev, ino)) ::unlink(lock.c_str());
    ::close(lock_fd);
  }
  const std::string prefix = temporary_prefix(target.file);
  std::error_code ec;
  for (fs::directory_iterator it(target.directory, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    // HOST-NS-PID-XXXXXX, read from the right (a host name may contain '-').
    const std::string rest = name.substr(prefix.size());
    const auto p3 = rest.rfind('-');
    if (p3 == std::string::npos || p3 == 0 || rest.size() - p3 - 1 != 6) continue;
    const auto p2 = rest.rfind('-', p3 - 1);
    if (p2 == std::string::npos || p2 == 0) continue;
    const auto p1 = rest.rfind('-', p2 - 1);
    if (p1 == std::string::npos) continue;
    const std::string host = rest.substr(0, p1), ns = rest.substr(p1 + 1, p2 - p1 - 1), pid = rest.substr(p2 + 1, p3 - p2 - 1);
    if (host != me.host || ns != me.ns || !all_digits(pid) || pid == me.pid) continue;
    const long long n = std::stoll(pid);
    if (n <= 0 || n > INT_MAX) continue;
    if (::kill(static_cast<pid_t>(n), 0) == 0 || errno != ESRCH) continue;  // alive (or not ours to ask)
    struct stat st;
    if (::lstat(it->path().c_str(), &st) != 0 || !S_ISREG(st.st_mode) || st.st_uid != ::geteuid()) continue;
    if (::unlink(it->path().c_str()) == 0)
      removed.push_back("removed " + (target.file.parent_path() / name).string() + ", left by gdsmc process " + pid +
                        " of this host, which no longer runs");
  }
  return removed;
}

}  // namespace gdsmc::host
