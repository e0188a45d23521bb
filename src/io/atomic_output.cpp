#include "seqtopo/io/atomic_output.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <mutex>
#include <optional>
#include <set>
#include <stdexcept>
#include <system_error>
#include <thread>

#include "seqtopo/core/input_error.hpp"
#include "seqtopo/io/sha256.hpp"

namespace seqtopo::io {
namespace fs = std::filesystem;

namespace {

// What this process must remove if it is stopped: staging folders, temporary files, old sets being removed.
struct Registry {
  std::mutex mutex;
  std::vector<fs::path> paths;
  bool committed = false;  // a commit has put its set in place
};

std::atomic<bool> stop_holds_lock{false};  // begin_stop() holds the registry's mutex (for good)

Registry& registry() {
  static auto* r = new Registry;  // never destroyed: a signal may come during static destruction
  return *r;
}

void track_locked(Registry& r, const fs::path& p) { r.paths.push_back(p); }

void untrack(const fs::path& p) {
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  r.paths.erase(std::remove(r.paths.begin(), r.paths.end(), p), r.paths.end());
}

std::uint64_t next_serial() {
  static std::atomic<std::uint64_t> serial{0};
  return serial++;
}

// remove_all, retried while a writer on another thread still adds files to the folder.
void remove_tree(const fs::path& p) {
  for (int attempt = 0; attempt < 50; ++attempt) {
    std::error_code ec;
    fs::remove_all(p, ec);
    if (!fs::exists(fs::symlink_status(p, ec))) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

std::string error_text(int error) { return std::error_code(error, std::generic_category()).message(); }

// fsync of a file or folder; failures are reported only for files (some file systems refuse it on folders).
void sync_path(const fs::path& p, bool directory) {
  const int fd = ::open(p.c_str(), (directory ? O_RDONLY | O_DIRECTORY : O_RDONLY) | O_CLOEXEC);
  if (fd < 0) {
    if (directory) return;
    throw InputError(p.string(), "cannot open to sync: " + error_text(errno));
  }
  const int rc = ::fsync(fd);
  const int error = errno;
  ::close(fd);
  if (rc != 0 && !directory && error != EINVAL) throw InputError(p.string(), "cannot sync: " + error_text(error));
}

void write_bytes(const fs::path& path, std::initializer_list<std::string_view> pieces, const std::string& subject) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) throw InputError(subject, "cannot open for writing: " + error_text(errno));
  // The file's blocks at once, not page by page as the writes come: several times faster for the large .npy
  // files. KEEP_SIZE: a failed write never leaves a zero tail that looks like content. Advisory (EOPNOTSUPP).
  std::size_t total = 0;
  for (const std::string_view bytes : pieces) total += bytes.size();
  if (total > 0) (void)::fallocate(fd, FALLOC_FL_KEEP_SIZE, 0, static_cast<off_t>(total));
  for (const std::string_view bytes : pieces) {
    std::size_t done = 0;
    while (done < bytes.size()) {
      const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        const int error = errno;
        ::close(fd);
        throw InputError(subject, "write failed: " + error_text(error));
      }
      done += static_cast<std::size_t>(n);
    }
  }
  if (::fsync(fd) != 0 && errno != EINVAL) {
    const int error = errno;
    ::close(fd);
    throw InputError(subject, "write failed: " + error_text(error));
  }
  if (::close(fd) != 0) throw InputError(subject, "write failed: " + error_text(errno));
}

// "<prefix><pid>-<k>" or "<prefix><pid>.<k>": the pid, when `name` starts with prefix and a number follows.
std::optional<pid_t> owner_pid(const std::string& name, const std::string& prefix) {
  if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) return std::nullopt;
  long pid = 0;
  std::size_t k = prefix.size();
  for (; k < name.size() && name[k] >= '0' && name[k] <= '9' && pid < (1L << 30); ++k) pid = pid * 10 + (name[k] - '0');
  if (k == prefix.size() || pid <= 0) return std::nullopt;
  return static_cast<pid_t>(pid);
}

// A leftover of a process that no longer runs: its pid is gone and nobody holds the folder's lock.
bool stale(const fs::path& p, pid_t pid, bool directory) {
  if (pid == ::getpid()) return false;
  if (::kill(pid, 0) == 0 || errno == EPERM) return false;  // alive (or a reused pid: left for a later run)
  if (!directory) return true;
  const int fd = ::open(p.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return true;
  const bool unlocked = ::flock(fd, LOCK_EX | LOCK_NB) == 0;
  ::close(fd);
  return unlocked;
}

// Removes `folder`'s entries named <prefix><pid>... of processes that no longer run.
void remove_stale(const fs::path& folder, const std::vector<std::string>& prefixes) {
  std::error_code ec;
  std::vector<fs::path> dead;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    for (const auto& prefix : prefixes) {
      const auto pid = owner_pid(name, prefix);
      if (pid && stale(it->path(), *pid, it->is_directory(ec))) dead.push_back(it->path());
    }
  }
  for (const auto& p : dead) remove_tree(p);
}

// The lock of an output folder: a file beside it, `.<name>.seqtopo-lock`, held with flock(2) by the one run that
// writes the folder, from its checks to the end of its swap (the kernel releases it when the run dies). Its holder
// removes it while it holds it; whoever locked a file that was removed meanwhile takes the new one.
bool same_file(int fd, const fs::path& path) {
  struct stat held {
  }, now{};
  return ::fstat(fd, &held) == 0 && ::stat(path.c_str(), &now) == 0 && held.st_dev == now.st_dev &&
         held.st_ino == now.st_ino;
}

int take_folder_lock(const fs::path& lock, const fs::path& shown) {
  for (int attempt = 0; attempt < 1000; ++attempt) {
    const int fd = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd < 0) {
      throw InputError(shown.string(),
                       "cannot make its lock file " + lock.filename().string() + ": " + error_text(errno));
    }
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int error = errno;
      std::array<char, 32> text{};
      const ssize_t n = ::pread(fd, text.data(), text.size() - 1, 0);
      ::close(fd);
      if (error != EWOULDBLOCK) throw InputError(shown.string(), "cannot lock: " + error_text(error));
      const std::string holder =
          n > 0 ? " (process " + std::string(text.data(), static_cast<std::size_t>(n)) + ")" : "";
      throw InputError(shown.string(), "is being written by another seqtopo run" + holder +
                                           "; two runs never write one folder at once: wait for it to finish, or "
                                           "choose another folder");
    }
    if (same_file(fd, lock)) {
      const std::string pid = std::to_string(::getpid());
      if (::ftruncate(fd, 0) == 0) (void)::pwrite(fd, pid.data(), pid.size(), 0);  // for the message above
      return fd;
    }
    ::close(fd);  // its holder removed it meanwhile: take the new one
  }
  throw InputError(shown.string(), "cannot lock: its lock file " + lock.filename().string() + " keeps changing");
}

// Removes the lock file (while it is held, so that nobody else holds this one) and releases it.
void release_folder_lock(const fs::path& lock, int& fd) {
  if (fd < 0) return;
  if (same_file(fd, lock)) ::unlink(lock.c_str());
  ::close(fd);
  fd = -1;
}

// ".<folder>.seqtopo-staging-<pid>-<k>" or ".<folder>.seqtopo-old-<pid>-<k>", of any folder: the owner's pid.
std::optional<pid_t> sibling_owner(const std::string& name) {
  const auto digits = [](std::string_view t) {
    return !t.empty() && std::all_of(t.begin(), t.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  if (name.size() < 2 || name[0] != '.') return std::nullopt;
  for (const std::string_view marker : {".seqtopo-staging-", ".seqtopo-old-"}) {
    const auto at = name.rfind(marker);
    if (at == std::string::npos || at == 0) continue;
    const std::string_view rest = std::string_view(name).substr(at + marker.size());
    const auto dash = rest.find('-');
    if (dash == std::string_view::npos || !digits(rest.substr(0, dash)) || !digits(rest.substr(dash + 1))) continue;
    return owner_pid(std::string(rest), "");
  }
  return std::nullopt;
}

// Removes the staging folders and old sets of every output folder in `folder` whose process no longer runs (killed):
// a run cleans what killed runs left beside it, whichever folder they were writing.
void remove_stale_siblings(const fs::path& folder) {
  std::error_code ec;
  std::vector<fs::path> dead;
  std::vector<fs::path> locks;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (it->is_symlink(ec)) continue;
    if (it->is_regular_file(ec) && name.size() > 14 && name[0] == '.' && name.ends_with(".seqtopo-lock")) {
      locks.push_back(it->path());
      continue;
    }
    if (!it->is_directory(ec)) continue;
    const auto pid = sibling_owner(name);
    if (pid && stale(it->path(), *pid, true)) dead.push_back(it->path());
  }
  for (const auto& p : dead) remove_tree(p);
  // A lock file nobody holds was left by a killed run: removed as its holder would (locked, then unlinked).
  for (const auto& p : locks) {
    int fd = ::open(p.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
    if (fd < 0) continue;
    if (::flock(fd, LOCK_EX | LOCK_NB) == 0) {
      release_folder_lock(p, fd);
    } else {
      ::close(fd);
    }
  }
}

// The name a folder's or file's hidden siblings start with: the name itself up to kShortName bytes; a longer one
// (a valid name is up to 255 bytes, the siblings add up to 50) is cut at a character boundary and ends with 8 hex
// digits of its SHA-256, so that every sibling's name stays well under the file system's limit.
constexpr std::size_t kShortName = 128;
std::string short_base(const std::string& base) {
  if (base.size() <= kShortName) return base;
  std::size_t cut = kShortName - 9;
  while (cut > 0 && (static_cast<unsigned char>(base[cut]) & 0xC0) == 0x80) --cut;  // not inside a UTF-8 character
  return base.substr(0, cut) + "~" + sha256_hex(base).substr(0, 8);
}

std::string staging_prefix(const std::string& base) { return "." + short_base(base) + ".seqtopo-staging-"; }
std::string old_prefix(const std::string& base) { return "." + short_base(base) + ".seqtopo-old-"; }
std::string temporary_prefix(const std::string& base) { return "." + short_base(base) + ".tmp."; }
std::string lock_name(const std::string& base) { return "." + short_base(base) + ".seqtopo-lock"; }

// `p` made absolute and normal, without a trailing separator.
fs::path normal_absolute(const fs::path& p) {
  fs::path a = fs::absolute(p).lexically_normal();
  if (a.filename().empty() && a.has_parent_path() && a != a.root_path()) a = a.parent_path();
  return a;
}

// True when `inner` is `outer` or lies inside it (component by component).
bool is_within(const fs::path& inner, const fs::path& outer) {
  auto i = inner.begin();
  for (auto o = outer.begin(); o != outer.end(); ++o, ++i) {
    if (o->empty()) continue;  // trailing separator
    if (i == inner.end() || *i != *o) return false;
  }
  return true;
}

fs::path resolved(const fs::path& p) {
  std::error_code ec;
  fs::path r = fs::weakly_canonical(fs::absolute(p), ec);
  return ec ? normal_absolute(p) : normal_absolute(r);
}

std::string json_string(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      std::array<char, 8> escape{};
      std::snprintf(escape.data(), escape.size(), "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
      out += escape.data();
    } else {
      out += c;
    }
  }
  return out + "\"";
}

// A tiny reader of the one JSON shape manifest_json writes.
class ManifestReader {
 public:
  ManifestReader(std::string_view text, const std::string& subject) : text_(text), subject_(subject) {}

  Manifest read() {
    Manifest m;
    bool have_version = false, have_files = false;
    expect('{');
    if (!peek('}')) {
      do {
        const std::string key = string();
        expect(':');
        if (key == "seqtopo_manifest") {
          if (number() != 1) fail("unsupported manifest version");
          have_version = true;
        } else if (key == "command") {
          m.command = string();
        } else if (key == "files") {
          files(m);
          have_files = true;
        } else {
          fail("unknown key '" + key + "'");
        }
      } while (take(','));
    }
    expect('}');
    space();
    if (pos_ != text_.size()) fail("text after the manifest");
    if (!have_version || !have_files) fail("not a seqtopo manifest (no seqtopo_manifest or files)");
    return m;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(subject_, "not a valid manifest: " + what + " (at byte " + std::to_string(pos_) + ")");
  }
  void space() {
    while (pos_ < text_.size() &&
           (text_[pos_] == ' ' || text_[pos_] == '\n' || text_[pos_] == '\t' || text_[pos_] == '\r')) {
      ++pos_;
    }
  }
  bool peek(char c) {
    space();
    return pos_ < text_.size() && text_[pos_] == c;
  }
  bool take(char c) {
    if (!peek(c)) return false;
    ++pos_;
    return true;
  }
  void expect(char c) {
    if (!take(c)) fail(std::string("expected '") + c + "'");
  }
  std::string string() {
    expect('"');
    std::string out;
    while (pos_ < text_.size() && text_[pos_] != '"') {
      char c = text_[pos_++];
      if (static_cast<unsigned char>(c) < 0x20) fail("control character in a string");
      if (c == '\\') {
        if (pos_ >= text_.size()) break;
        c = text_[pos_++];
        if (c == 'u') {
          if (pos_ + 4 > text_.size()) fail("short \\u escape");
          unsigned value = 0;
          for (int k = 0; k < 4; ++k) {
            const char h = text_[pos_++];
            const int digit = h >= '0' && h <= '9'   ? h - '0'
                              : h >= 'a' && h <= 'f' ? h - 'a' + 10
                              : h >= 'A' && h <= 'F' ? h - 'A' + 10
                                                     : -1;
            if (digit < 0) fail("bad \\u escape");
            value = value * 16 + static_cast<unsigned>(digit);
          }
          if (value >= 0x20) fail("\\u escape of a printable character");
          c = static_cast<char>(value);
        } else if (c != '"' && c != '\\' && c != '/') {
          fail("unknown escape");
        }
      }
      out += c;
    }
    if (pos_ >= text_.size()) fail("unterminated string");
    ++pos_;
    return out;
  }
  std::uint64_t number() {
    space();
    const std::size_t start = pos_;
    std::uint64_t value = 0;
    while (pos_ < text_.size() && text_[pos_] >= '0' && text_[pos_] <= '9') {
      const auto digit = static_cast<std::uint64_t>(text_[pos_] - '0');
      if (value > (UINT64_MAX - digit) / 10) fail("number too large");
      value = value * 10 + digit;
      ++pos_;
    }
    if (pos_ == start) fail("expected a number");
    return value;
  }
  void files(Manifest& m) {
    expect('[');
    if (take(']')) return;
    do {
      ManifestEntry e;
      bool name = false, bytes = false, sha = false;
      expect('{');
      do {
        const std::string key = string();
        expect(':');
        if (key == "name") {
          e.name = string();
          name = true;
        } else if (key == "bytes") {
          e.bytes = number();
          bytes = true;
        } else if (key == "sha256") {
          e.sha256 = string();
          sha = e.sha256.size() == 64 && std::all_of(e.sha256.begin(), e.sha256.end(), [](char c) {
                  return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
                });
          if (!sha) fail("sha256 is not 64 hex digits");
        } else {
          fail("unknown key '" + key + "' of a file");
        }
      } while (take(','));
      expect('}');
      if (!name || !bytes || !sha) fail("a file needs name, bytes and sha256");
      const fs::path p(e.name);
      if (e.name.empty() || p.is_absolute() ||
          std::any_of(p.begin(), p.end(), [](const fs::path& part) { return part == ".." || part == "."; })) {
        fail("file name '" + e.name + "' is not a plain relative path");
      }
      m.files.push_back(std::move(e));
    } while (take(','));
    expect(']');
  }

  std::string_view text_;
  std::string subject_;
  std::size_t pos_ = 0;
};

std::string read_whole(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "cannot open file");
  std::string text((std::istreambuf_iterator<char>(in)), {});
  if (in.bad()) throw InputError(path.string(), "cannot read file");
  return text;
}

// SHA-256 of a file, read in pieces.
std::string hash_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "cannot open file");
  Sha256 h;
  std::vector<char> buffer(1 << 20);
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    h.update({buffer.data(), static_cast<std::size_t>(in.gcount())});
  }
  if (in.bad()) throw InputError(path.string(), "cannot read file");
  return h.hex();
}

// Relative '/'-separated paths of the regular files under `dir` (sorted), and of its folders; anything else
// (a symbolic link, a device) is returned in `other`.
struct Tree {
  std::vector<std::string> files, folders, other;
};

Tree list_tree(const fs::path& dir) {
  Tree t;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(dir, fs::directory_options::none, ec), end; !ec && it != end;
       it.increment(ec)) {
    const std::string rel = it->path().lexically_relative(dir).generic_string();
    const auto status = it->symlink_status(ec);
    if (fs::is_symlink(status)) {
      t.other.push_back(rel);
    } else if (fs::is_directory(status)) {
      t.folders.push_back(rel);
    } else if (fs::is_regular_file(status)) {
      t.files.push_back(rel);
    } else {
      t.other.push_back(rel);
    }
  }
  if (ec) throw InputError(dir.string(), "cannot list: " + ec.message());
  std::sort(t.files.begin(), t.files.end());
  return t;
}

// Throws unless `target` may be replaced whole: absent, an empty folder, or a folder whose manifest lists every
// file in it, each as the manifest has it (size and SHA-256: a file the user edited would be lost). `shown` is the
// folder as the user gave it. `seen` keeps what matched (the manifest, and each file's size, time and inode), so
// that the check before the swap hashes again only the files that changed since.
void check_replaceable(const fs::path& target, const fs::path& shown, OldSetSeen& seen) {
  std::error_code ec;
  const auto status = fs::symlink_status(target, ec);
  if (!fs::exists(status)) return;
  if (!fs::is_directory(status)) throw InputError(shown.string(), "exists and is not a folder");
  if (fs::is_empty(target, ec)) return;
  const fs::path manifest = target / kManifestName;
  if (!fs::exists(fs::symlink_status(manifest, ec))) {
    throw InputError(shown.string(),
                     "is not empty and has no manifest.json of an earlier seqtopo run; an output folder is replaced "
                     "whole, so give a new or empty folder (or remove this one)");
  }
  const std::string manifest_text = read_whole(manifest);
  const Manifest m = parse_manifest(manifest_text, manifest.string());
  if (manifest_text != seen.manifest) {
    seen.manifest = manifest_text;
    seen.files.clear();
  }
  std::set<std::string> listed{kManifestName}, folders;
  for (const auto& f : m.files) {
    listed.insert(f.name);
    for (fs::path p = fs::path(f.name).parent_path(); !p.empty(); p = p.parent_path())
      folders.insert(p.generic_string());
  }
  const Tree tree = list_tree(target);
  const auto foreign = [&](const std::string& rel) {
    throw InputError(shown.string(), "holds '" + rel +
                                         "', which its manifest.json does not list (no seqtopo run wrote it); an "
                                         "output folder is replaced whole, so move it away or choose another folder");
  };
  for (const auto& f : tree.files) {
    if (!listed.count(f)) foreign(f);
  }
  for (const auto& f : tree.folders) {
    if (!folders.count(f)) foreign(f + "/");
  }
  if (!tree.other.empty()) foreign(tree.other.front());
  for (const auto& f : m.files) {
    const fs::path p = target / f.name;
    struct stat st {};
    if (::lstat(p.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) continue;  // missing: nothing to lose
    const std::string key = std::to_string(st.st_size) + " " + std::to_string(st.st_mtim.tv_sec) + "." +
                            std::to_string(st.st_mtim.tv_nsec) + " " + std::to_string(st.st_ino);
    const auto known = seen.files.find(f.name);
    if (known != seen.files.end() && known->second == key) continue;
    const bool size = static_cast<std::uint64_t>(st.st_size) != f.bytes;
    if (size || hash_file(p) != f.sha256) {
      throw InputError(shown.string(), "holds '" + f.name + "', changed since the seqtopo run that wrote it (its " +
                                           (size ? "size" : "SHA-256") +
                                           " is not the one in manifest.json); an output folder is replaced whole, "
                                           "so move the file away (or remove the folder) to replace it");
    }
    seen.files[f.name] = key;
  }
}

}  // namespace

void write_file_atomic(const fs::path& path, std::string_view bytes) {
  const fs::path parent = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  const std::string base = path.filename().string();
  if (base.empty()) throw InputError(path.string(), "is not a file name");
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw InputError(path.string(), "is a folder");
  if (!fs::is_directory(parent, ec)) throw InputError(path.string(), "its folder does not exist");
  remove_stale(parent, {temporary_prefix(base)});
  const fs::path tmp =
      parent / (temporary_prefix(base) + std::to_string(::getpid()) + "." + std::to_string(next_serial()));
  {
    Registry& r = registry();
    const std::lock_guard lock(r.mutex);
    track_locked(r, tmp);
  }
  try {
    write_bytes(tmp, {bytes}, path.string());
  } catch (...) {
    fs::remove(tmp, ec);
    untrack(tmp);
    throw;
  }
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    const int error = errno;
    fs::remove(tmp, ec);
    untrack(tmp);
    throw InputError(path.string(), "cannot move into place: " + error_text(error));
  }
  untrack(tmp);
  sync_path(parent, true);
}

std::string manifest_json(const Manifest& manifest) {
  std::vector<ManifestEntry> files = manifest.files;
  std::sort(files.begin(), files.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  std::string out = "{\"seqtopo_manifest\": 1, \"command\": " + json_string(manifest.command) + ", \"files\": [";
  for (std::size_t k = 0; k < files.size(); ++k) {
    out += k == 0 ? "\n" : ",\n";
    out += " {\"name\": " + json_string(files[k].name) + ", \"bytes\": " + std::to_string(files[k].bytes) +
           ", \"sha256\": \"" + files[k].sha256 + "\"}";
  }
  out += files.empty() ? "]}\n" : "\n]}\n";
  return out;
}

Manifest parse_manifest(std::string_view text, const std::string& subject) {
  return ManifestReader(text, subject).read();
}

Manifest read_manifest(const fs::path& dir) {
  const fs::path path = dir / kManifestName;
  return parse_manifest(read_whole(path), path.string());
}

std::string verify_manifest(const fs::path& dir) {
  const Manifest m = read_manifest(dir);
  std::string problems;
  const auto add = [&](const std::string& text) { problems += (problems.empty() ? "" : "; ") + text; };
  std::set<std::string> listed{kManifestName};
  for (const auto& f : m.files) {
    listed.insert(f.name);
    const fs::path p = dir / f.name;
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) {
      add(f.name + " missing");
      continue;
    }
    if (fs::file_size(p, ec) != f.bytes) {
      add(f.name + " has another size");
    } else if (hash_file(p) != f.sha256) {
      add(f.name + " has another SHA-256");
    }
  }
  const Tree tree = list_tree(dir);
  for (const auto& f : tree.files) {
    if (!listed.count(f)) add(f + " not listed");
  }
  for (const auto& f : tree.other) add(f + " not listed");
  return problems;
}

OutputDirectory::OutputDirectory(fs::path dir, OutputOptions options)
    : dir_(std::move(dir)), options_(std::move(options)) {
  if (dir_.empty()) throw InputError("output folder", "no folder given");
  target_ = normal_absolute(dir_);
  std::error_code ec;
  if (fs::is_symlink(target_, ec)) {
    target_ = fs::canonical(target_, ec);  // replace the folder the link points to, keep the link
    if (ec) throw InputError(dir_.string(), "is a symbolic link to nothing");
  }
  if (target_ == target_.root_path() || target_.filename().empty()) {
    throw InputError(dir_.string(), "the root folder cannot be an output folder");
  }
  const fs::path real = resolved(target_);
  for (const auto& input : options_.inputs) {
    if (input.empty() || input == "-" || !fs::exists(input, ec)) continue;
    const fs::path in = resolved(input);
    if (in == real)
      throw InputError(dir_.string(), "is the input " + input.string() + "; choose another output folder");
    if (is_within(in, real)) {
      throw InputError(dir_.string(), "holds the input " + input.string() +
                                          "; an output folder is replaced whole, so choose another one");
    }
    if (is_within(real, in)) {
      throw InputError(dir_.string(), "is inside the input folder " + input.string() +
                                          "; outputs are never written into an input folder");
    }
  }
  const fs::path cwd = fs::current_path(ec);
  if (!ec && is_within(resolved(cwd), real)) {
    throw InputError(dir_.string(),
                     "holds the current folder; an output folder is replaced whole, so run from "
                     "outside it or choose another one");
  }
  const fs::path parent = target_.parent_path();
  const std::string base = target_.filename().string();
  for (fs::path p = parent; !p.empty() && !fs::exists(p, ec); p = p.parent_path()) {
    made_parents_.push_back(p);
    if (p == p.root_path()) break;
  }
  fs::create_directories(parent, ec);
  if (ec || !fs::is_directory(parent)) {
    throw InputError(dir_.string(), "cannot create its parent folder: " + (ec ? ec.message() : "not a folder"));
  }
  remove_stale_siblings(parent);
  try {
    {
      // The folder's lock first: a second run writing the same folder is refused before any work.
      Registry& r = registry();
      const std::lock_guard lock(r.mutex);
      lock_file_ = parent / lock_name(base);
      folder_lock_fd_ = take_folder_lock(lock_file_, dir_);
      track_locked(r, lock_file_);  // a stopped run removes it with its staging folder
    }
    check_replaceable(target_, dir_, old_set_);
    Registry& r = registry();
    const std::lock_guard lock(r.mutex);
    for (;;) {
      staging_ = parent / (staging_prefix(base) + std::to_string(::getpid()) + "-" + std::to_string(next_serial()));
      if (::mkdir(staging_.c_str(), 0777) == 0) break;
      if (errno != EEXIST) throw InputError(dir_.string(), "cannot write beside it: " + error_text(errno));
    }
    track_locked(r, staging_);
  } catch (...) {
    if (folder_lock_fd_ >= 0) {
      release_folder_lock(lock_file_, folder_lock_fd_);
      untrack(lock_file_);
    }
    for (const auto& p : made_parents_) fs::remove(p, ec);  // only what is still empty
    throw;
  }
  lock_fd_ = ::open(staging_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (lock_fd_ >= 0) (void)::flock(lock_fd_, LOCK_EX | LOCK_NB);
  // The new set keeps the old folder's permissions.
  if (fs::is_directory(target_, ec)) fs::permissions(staging_, fs::status(target_, ec).permissions(), ec);
}

OutputDirectory::~OutputDirectory() {
  if (!committed_ && !staging_.empty()) {
    remove_tree(staging_);
    untrack(staging_);
    std::error_code ec;
    for (const auto& p : made_parents_) fs::remove(p, ec);
  }
  if (lock_fd_ >= 0) ::close(lock_fd_);
  if (folder_lock_fd_ >= 0) {
    release_folder_lock(lock_file_, folder_lock_fd_);
    untrack(lock_file_);
  }
}

fs::path OutputDirectory::staged(const std::string& name) {
  const fs::path relative(name);
  if (name.empty() || relative.is_absolute() || name == kManifestName ||
      std::any_of(relative.begin(), relative.end(), [](const fs::path& p) { return p == ".." || p == "."; })) {
    throw std::invalid_argument("OutputDirectory: '" + name + "' is not a plain relative name (or is the manifest's)");
  }
  if (committed_) throw std::logic_error("OutputDirectory: staged() after commit()");
  if (std::find(names_.begin(), names_.end(), name) == names_.end()) names_.push_back(name);
  const fs::path path = staging_ / relative;
  std::error_code ec;
  fs::create_directories(path.parent_path(), ec);
  return path;
}

void OutputDirectory::write(const std::string& name, std::string_view bytes) { write_pieces(name, {bytes}); }

void OutputDirectory::write_pieces(const std::string& name, std::initializer_list<std::string_view> pieces) {
  const fs::path path = staged(name);
  write_bytes(path, pieces, (dir_ / name).string());
  Sha256 h;
  std::uint64_t size = 0;
  for (const std::string_view bytes : pieces) h.update(bytes), size += bytes.size();
  hashes_[fs::path(name).generic_string()] = {size, h.hex()};
}

std::vector<fs::path> OutputDirectory::commit() {
  if (committed_) throw std::logic_error("OutputDirectory: commit() twice");
  for (const auto& name : names_) {
    std::error_code ec;
    if (!fs::exists(staging_ / name, ec)) throw InputError((dir_ / name).string(), "was never written");
  }
  // The manifest: every file of the staged set (also those writers made themselves), synced to disk.
  const Tree tree = list_tree(staging_);
  if (!tree.other.empty()) throw InputError((dir_ / tree.other.front()).string(), "is not a regular file");
  Manifest manifest{options_.command, {}};
  for (const auto& rel : tree.files) {
    const fs::path p = staging_ / rel;
    std::error_code ec;
    ManifestEntry e{rel, fs::file_size(p, ec), {}};
    if (ec) throw InputError((dir_ / rel).string(), "cannot read its size: " + ec.message());
    const auto known = hashes_.find(rel);
    if (known != hashes_.end() && known->second.first == e.bytes) {
      e.sha256 = known->second.second;  // as write() wrote it (and synced it)
    } else {
      e.sha256 = hash_file(p);
      sync_path(p, false);
    }
    manifest.files.push_back(std::move(e));
  }
  write_bytes(staging_ / kManifestName, {manifest_json(manifest)}, (dir_ / kManifestName).string());
  for (const auto& f : tree.folders) sync_path(staging_ / f, true);
  sync_path(staging_, true);

  const fs::path parent = target_.parent_path();
  const std::string base = target_.filename().string();
  fs::path old;  // where the old set is after the swap (to be removed)
  {
    Registry& r = registry();
    const std::lock_guard lock(r.mutex);         // a stopping process waits for the swap, then removes what is left
    check_replaceable(target_, dir_, old_set_);  // again: the folder may have changed during the run
    std::error_code ec;
    bool exists = fs::exists(fs::symlink_status(target_, ec));
    if (!exists) {
      if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, target_.c_str(), RENAME_NOREPLACE) == 0) {
        r.paths.erase(std::remove(r.paths.begin(), r.paths.end(), staging_), r.paths.end());
      } else if (errno == EEXIST) {
        exists = true;  // made meanwhile: swap with it below (it was empty or a seqtopo set, checked above)
      } else if ((errno == EINVAL || errno == ENOSYS) && ::rename(staging_.c_str(), target_.c_str()) == 0) {
        r.paths.erase(std::remove(r.paths.begin(), r.paths.end(), staging_), r.paths.end());
      } else {
        throw InputError(dir_.string(), "cannot move the new set into place: " + error_text(errno));
      }
    }
    if (exists) {
      if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, target_.c_str(), RENAME_EXCHANGE) == 0) {
        old = staging_;  // the old set now has the staging folder's name (and stays tracked until removed)
      } else if (errno == EINVAL || errno == ENOSYS || errno == ENOTSUP) {
        // No exchange on this file system: the old set moves aside, the new one in, the old back on failure.
        // Between the two renames the folder is absent, never mixed.
        old = parent / (old_prefix(base) + std::to_string(::getpid()) + "-" + std::to_string(next_serial()));
        track_locked(r, old);
        if (::rename(target_.c_str(), old.c_str()) != 0) {
          const int error = errno;
          r.paths.pop_back();
          throw InputError(dir_.string(), "cannot move the old set aside: " + error_text(error));
        }
        if (::rename(staging_.c_str(), target_.c_str()) != 0) {
          const int error = errno;
          (void)::rename(old.c_str(), target_.c_str());
          r.paths.pop_back();
          throw InputError(dir_.string(), "cannot move the new set into place: " + error_text(error));
        }
        r.paths.erase(std::remove(r.paths.begin(), r.paths.end(), staging_), r.paths.end());
      } else {
        throw InputError(dir_.string(), "cannot replace the old set: " + error_text(errno));
      }
    }
    committed_ = true;
    r.committed = true;
  }
  sync_path(parent, true);
  if (!old.empty()) {
    remove_tree(old);
    untrack(old);
  }
  if (lock_fd_ >= 0) {
    ::close(lock_fd_);
    lock_fd_ = -1;
  }
  release_folder_lock(lock_file_, folder_lock_fd_);
  untrack(lock_file_);
  std::vector<fs::path> written;
  for (const auto& name : names_) written.push_back(dir_ / name);
  return written;
}

bool begin_stop() {
  Registry& r = registry();
  r.mutex.lock();  // a swap in progress finishes first
  if (r.committed) {
    r.mutex.unlock();
    return false;
  }
  stop_holds_lock = true;  // never unlocked: no output folder changes after this point
  return true;
}

void remove_staged_outputs_and_exit(int status) {
  Registry& r = registry();
  if (!stop_holds_lock) r.mutex.lock();  // never unlocked: no output folder changes after this point
  for (const auto& p : r.paths) remove_tree(p);
  ::_exit(status);
}

}  // namespace seqtopo::io
