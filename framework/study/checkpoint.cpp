#include "study/checkpoint.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <set>

#include <yaml-cpp/yaml.h>

#include <gdsmc/version.hpp>

namespace gdsmc::host {

namespace fs = std::filesystem;

namespace {

constexpr const char* kFormat = "gdsmc checkpoint";
constexpr std::uint32_t kFormatVersion = 2;  // 2: the engine keeps its stage times (engine.stage_seconds)

std::string errno_text() { return std::strerror(errno); }

// Entries straight into a file (a state of 10^7 particles is never held twice in memory).
class FileStateWriter final : public StateWriter {
 public:
  explicit FileStateWriter(const fs::path& path) : path_(path) {
    file_ = std::fopen(path.c_str(), "wb");
    if (!file_) throw std::runtime_error("cannot create " + path.string() + ": " + errno_text());
    std::setvbuf(file_, nullptr, _IOFBF, 1 << 20);
  }
  ~FileStateWriter() override {
    if (file_) std::fclose(file_);
  }
  // Flush, fsync and close; throws on any error (disk full).
  void close() {
    const bool ok = std::fflush(file_) == 0 && ::fsync(::fileno(file_)) == 0;
    const int saved = errno;
    const bool closed = std::fclose(file_) == 0;
    file_ = nullptr;
    if (!ok || !closed) {
      errno = ok ? errno : saved;
      throw std::runtime_error("cannot write " + path_.string() + ": " + errno_text());
    }
  }

 protected:
  void put(const void* data, std::size_t bytes) override {
    if (std::fwrite(data, 1, bytes, file_) != bytes)
      throw std::runtime_error("cannot write " + path_.string() + ": " + errno_text());
  }

 private:
  fs::path path_;
  std::FILE* file_ = nullptr;
};

class FileStateReader final : public StateReader {
 public:
  explicit FileStateReader(const fs::path& path) : path_(path) {
    file_ = std::fopen(path.c_str(), "rb");
    if (!file_) throw CheckpointError("cannot read " + path.string() + ": " + errno_text());
    std::error_code ec;
    size_ = fs::file_size(path, ec);
    std::setvbuf(file_, nullptr, _IOFBF, 1 << 20);
  }
  ~FileStateReader() override { std::fclose(file_); }
  std::string peek_name() override {
    const long at = std::ftell(file_);
    std::uint32_t length = 0;
    std::string name;
    if (remaining() >= sizeof length && std::fread(&length, sizeof length, 1, file_) == 1 && length <= 4096 &&
        length <= remaining()) {
      name.resize(length);
      if (std::fread(name.data(), 1, length, file_) != length) name.clear();
    }
    std::fseek(file_, at, SEEK_SET);
    return name;
  }
  std::uint64_t remaining() const override { return size_ - at_; }
  bool at_end() const { return at_ == size_; }

 protected:
  void get(void* data, std::size_t bytes) override {
    if (bytes > remaining() || std::fread(data, 1, bytes, file_) != bytes)
      throw StateError(path_.string() + " is truncated (" + std::to_string(bytes) + " bytes wanted, " +
                       std::to_string(remaining()) + " left)");
    at_ += bytes;
  }

 private:
  fs::path path_;
  std::FILE* file_ = nullptr;
  std::uint64_t size_ = 0, at_ = 0;
};

// The pipeline as it decides the results: the resolved text without run.threads and
// run.checkpoint, which do not change a bit of the output (a resume may use other values).
std::string pipeline_identity(const Pipeline& p) {
  YAML::Node root = YAML::Load(p.resolved_text);
  if (root.IsMap() && root["run"] && root["run"].IsMap()) {
    root["run"].remove("threads");
    root["run"].remove("checkpoint");
  }
  YAML::Emitter e;
  e << root;
  return e.c_str();
}

std::string plugin_lines(const Pipeline& p) {
  std::string t;
  auto line = [&](const PluginUse& u) {
    t += u.path + ": " + u.plugin->descriptor->name + " " + u.plugin->descriptor->version + "\n";
  };
  line(p.initial_state);
  line(p.collision);
  for (const auto* uses : {&p.forcings, &p.boundaries, &p.diagnostics})
    for (const auto& u : *uses) line(u);
  return t;
}

// The head of a run file, before the engine's state: what the file is and whose run it holds.
struct RunHeader {
  std::string format, version, plugins;
  std::uint64_t run = 0;
  std::uint32_t realization = 0;
};
void write_run_header(StateWriter& w, const RunHeader& h) {
  w.write("format", h.format);
  w.write("gdsmc_version", h.version);
  w.write("run", h.run);
  w.write("realization", h.realization);
  w.write("plugins", h.plugins);
}
RunHeader read_run_header(StateReader& r) {
  RunHeader h;
  r.read("format", h.format);
  r.read("gdsmc_version", h.version);
  r.read("run", h.run);
  r.read("realization", h.realization);
  r.read("plugins", h.plugins);
  return h;
}

// The lines of a text, as a set.
std::set<std::string> line_set(const std::string& text) {
  std::set<std::string> lines;
  for (std::size_t a = 0, e; a < text.size(); a = e + 1) {
    e = text.find('\n', a);
    lines.insert(text.substr(a, e - a));
  }
  return lines;
}

// The first line where two texts differ, for a message.
std::string first_difference(const std::string& saved, const std::string& now) {
  std::size_t a = 0, b = 0;
  for (int line = 1;; ++line) {
    const std::size_t ea = saved.find('\n', a), eb = now.find('\n', b);
    const std::string la = saved.substr(a, ea == std::string::npos ? std::string::npos : ea - a);
    const std::string lb = now.substr(b, eb == std::string::npos ? std::string::npos : eb - b);
    if (la != lb) return "line " + std::to_string(line) + ": the checkpoint's '" + la + "', now '" + lb + "'";
    if (ea == std::string::npos || eb == std::string::npos) return "the length";
    a = ea + 1;
    b = eb + 1;
  }
}

}  // namespace

fs::path CheckpointStore::directory_for(const fs::path& output) {
  fs::path dir = output;
  dir += ".checkpoint";
  return dir;
}

CheckpointStore::CheckpointStore(fs::path dir, const std::vector<StudyCase>& cases, bool resume)
    : dir_(std::move(dir)), gdsmc_version_(version_string), pipeline_(pipeline_identity(cases.front().pipeline)) {
  std::set<std::string> all;  // every case's plugins (a sweep of named variants may change them)
  for (const auto& c : cases) {
    all.insert(plugin_lines(c.pipeline));
    runs_ += c.pipeline.realizations;
  }
  std::string plugins;
  for (const auto& t : all) plugins += t;
  const fs::path study = dir_ / "study";
  std::error_code ec;
  if (!resume) {
    if (fs::exists(study, ec))
      throw CheckpointError(dir_.string() + " holds the checkpoint of an earlier run with this output: continue it "
                            "with `gdsmc run ... --resume`, or remove the directory to start over");
    fs::create_directories(dir_, ec);
    if (ec) throw CheckpointError("cannot create the checkpoint directory " + dir_.string() + ": " + ec.message());
    const fs::path partial = dir_ / ".study.partial";
    FileStateWriter w(partial);
    w.write("format", std::string(kFormat));
    w.write("format_version", kFormatVersion);
    w.write("gdsmc_version", gdsmc_version_);
    w.write("pipeline", pipeline_);
    w.write("plugins", plugins);
    w.write("runs", static_cast<std::uint64_t>(runs_));
    w.close();
    fs::rename(partial, study, ec);
    if (ec) throw CheckpointError("cannot write " + study.string() + ": " + ec.message());
    return;
  }
  if (!fs::exists(study, ec))
    throw CheckpointError("--resume: there is no checkpoint at " + dir_.string() +
                          " (a run writes one there when its pipeline sets run.checkpoint)");
  // Temporaries of writes a kill interrupted.
  for (const auto& e : fs::directory_iterator(dir_, ec))
    if (e.path().filename().string().rfind(".", 0) == 0) fs::remove(e.path(), ec);
  std::vector<std::string> differences;
  try {
    FileStateReader r(study);
    std::string format, version, pipeline, saved_plugins;
    std::uint32_t format_version = 0;
    std::uint64_t runs = 0;
    r.read("format", format);
    r.read("format_version", format_version);
    if (format != kFormat || format_version != kFormatVersion)
      throw CheckpointError(study.string() + " is not a gdsmc checkpoint of format " + std::to_string(kFormatVersion));
    r.read("gdsmc_version", version);
    r.read("pipeline", pipeline);
    r.read("plugins", saved_plugins);
    r.read("runs", runs);
    if (version != gdsmc_version_)
      differences.push_back("it was written by gdsmc " + version + ", this is gdsmc " + gdsmc_version_);
    if (pipeline != pipeline_)
      differences.push_back("the pipeline (after --set; run.threads and run.checkpoint aside) differs at " +
                            first_difference(pipeline, pipeline_));
    if (saved_plugins != plugins) {
      // Name each plugin line that is not the same.
      const std::set<std::string> before = line_set(saved_plugins), after = line_set(plugins);
      std::string what;
      for (const auto& l : before)
        if (!after.count(l)) what += (what.empty() ? "" : "; ") + ("the checkpoint has " + l);
      for (const auto& l : after)
        if (!before.count(l)) what += (what.empty() ? "" : "; ") + ("this run has " + l);
      differences.push_back("the plugins differ: " + what);
    }
    if (runs != runs_ && pipeline == pipeline_)
      differences.push_back("it holds " + std::to_string(runs) + " runs, this study has " + std::to_string(runs_));
  } catch (const StateError& e) {
    throw CheckpointError(study.string() + " is damaged: " + e.what());
  }
  if (!differences.empty()) {
    std::string m = "--resume: the checkpoint " + dir_.string() + " belongs to another run: ";
    for (std::size_t k = 0; k < differences.size(); ++k) m += (k ? "; " : "") + differences[k];
    throw CheckpointError(m + ". Run without --resume after removing the directory to start over");
  }
}

fs::path CheckpointStore::run_file(std::size_t index) const { return dir_ / ("run-" + std::to_string(index)); }

bool CheckpointStore::has_run(std::size_t index) const {
  std::error_code ec;
  return fs::exists(run_file(index), ec);
}

std::string CheckpointStore::describe(const std::vector<StudyCase>& cases) const {
  std::size_t finished = 0, under_way = 0, run = 0;
  double t_min = 0, t_max = 0;  // t/tau0 of the runs under way
  for (const auto& c : cases) {
    const double tau0 = c.pipeline.system_info(c.pipeline.particles, 0).time_unit0;
    for (std::uint32_t r = 0; r < c.pipeline.realizations; ++r, ++run) {
      if (!has_run(run)) continue;
      try {
        FileStateReader in(run_file(run));
        read_run_header(in);
        const Engine::SavedProgress progress = Engine::saved_progress(in);
        if (progress.finished) {
          ++finished;
          continue;
        }
        const double t = progress.clocks[0] / tau0;
        t_min = under_way ? std::min(t_min, t) : t;
        t_max = under_way ? std::max(t_max, t) : t;
        ++under_way;
      } catch (const std::exception&) {
        // restore() says what is wrong with it
      }
    }
  }
  char range[96];
  std::snprintf(range, sizeof range, t_min == t_max ? "at t = %.4g tau0" : "at t = %.4g to %.4g tau0", t_min, t_max);
  std::string s = std::to_string(runs_) + (runs_ == 1 ? " run: " : " runs: ") + std::to_string(finished) + " finished, " +
                  std::to_string(under_way) + " under way";
  if (under_way) s += std::string(" (") + range + ")";
  return s + ", " + std::to_string(runs_ - finished - under_way) + " not started";
}

void CheckpointStore::write(std::size_t index, const StudyCase& c, std::uint32_t realization, const Engine& engine) const {
  const fs::path file = run_file(index);
  fs::path partial = dir_ / ("." + file.filename().string() + ".partial-" + std::to_string(::getpid()));
  std::error_code ec;
  try {
    FileStateWriter w(partial);
    write_run_header(w, RunHeader{kFormat, gdsmc_version_, plugin_lines(c.pipeline), index, realization});
    engine.save(w);
    w.close();
  } catch (const std::exception& e) {
    fs::remove(partial, ec);  // a failed write (disk full) leaves no partial file taking space
    throw std::runtime_error("checkpoint " + file.string() + " not written: " + e.what());
  }
  fs::rename(partial, file, ec);
  if (ec) throw std::runtime_error("cannot write " + file.string() + ": " + ec.message());
  const int d = ::open(dir_.c_str(), O_RDONLY | O_DIRECTORY);
  if (d >= 0) {
    ::fsync(d);  // the rename itself survives a crash
    ::close(d);
  }
}

std::unique_ptr<Engine> CheckpointStore::restore(std::size_t index, const StudyCase& c, std::uint32_t realization,
                                                 unsigned threads) const {
  const fs::path file = run_file(index);
  try {
    FileStateReader r(file);
    const RunHeader h = read_run_header(r);
    if (h.format != kFormat || h.version != gdsmc_version_ || h.run != index || h.realization != realization ||
        h.plugins != plugin_lines(c.pipeline))
      throw CheckpointError(file.string() + " is not the checkpoint of run " + std::to_string(index) + " (realization " +
                            std::to_string(realization) + ") of this study with gdsmc " + gdsmc_version_ +
                            " and these plugins");
    auto engine = std::make_unique<Engine>(c.pipeline, realization, threads, r);
    if (!r.at_end())
      throw CheckpointError(file.string() + ": " + std::to_string(r.remaining()) + " bytes left after the state (next entry '" +
                            r.peek_name() + "')");
    return engine;
  } catch (const StateError& e) {
    throw CheckpointError("cannot resume from " + file.string() + ": " + e.what());
  }
}

void CheckpointStore::remove() const {
  std::error_code ec;
  fs::remove_all(dir_, ec);
}

}  // namespace gdsmc::host
