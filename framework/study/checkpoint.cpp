#include "study/checkpoint.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <map>
#include <set>

#include <yaml-cpp/yaml.h>

#include "config/system_info.hpp"
#include "study/checkpoint_file.hpp"
#include "util/content_hash.hpp"

#include <gdsmc/version.hpp>

namespace gdsmc::host {

namespace fs = std::filesystem;

namespace {

constexpr const char* kFormat = "gdsmc checkpoint";
// 2: the engine keeps its stage times (engine.stage_seconds); 3: a checksum per entry, plugin
// libraries by content hash.
constexpr std::uint32_t kFormatVersion = 3;

// The pipeline as it decides the results: the resolved text without run.threads and
// run.checkpoint, which do not change a bit of the output (a resume may use other values).
std::string identity_of(const std::string& resolved_text) {
  YAML::Node root = YAML::Load(resolved_text);
  if (root.IsMap() && root["run"] && root["run"].IsMap()) {
    root["run"].remove("threads");
    root["run"].remove("checkpoint");
  }
  YAML::Emitter e;
  e << root;
  return e.c_str();
}

// One line per plugin: "ROLE: NAME VERSION (library HASH)", HASH its library file's content hash:
// a library rebuilt with other code but the same version string is another plugin.
constexpr const char* kLibraryMark = " (library ";
template <class F>
void for_each_use(const Pipeline& p, F&& f) {
  f(p.initial_state);
  f(p.collision);
  for (const auto* uses : {&p.forcings, &p.boundaries, &p.diagnostics})
    for (const auto& u : *uses) f(u);
}
// "ROLE: NAME VERSION".
std::string use_text(const PluginUse& u) {
  return u.path + ": " + u.plugin->descriptor->name + " " + u.plugin->descriptor->version;
}
std::string plugin_lines(const Pipeline& p) {
  std::string t;
  for_each_use(p, [&](const PluginUse& u) {
    t += use_text(u) + kLibraryMark + ContentHash::hex(u.plugin->content_hash) + ")\n";
  });
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

// The plugin lines of the checkpoint and of this run that differ, for a message.
std::string plugin_differences(const std::string& saved_plugins, const std::string& plugins,
                               const std::map<std::string, std::string>& libraries) {
  // Name each plugin line that is not the same: a library of the same plugin and version whose
  // content differs (rebuilt) with both hashes, any other difference as the two lines.
  const std::set<std::string> before = line_set(saved_plugins), after = line_set(plugins);
  auto identity = [](const std::string& l) { return l.substr(0, l.find(kLibraryMark)); };
  auto hash_of = [](const std::string& l) {
    const std::size_t at = l.find(kLibraryMark);
    return at == std::string::npos ? std::string("none") : l.substr(at + std::strlen(kLibraryMark), 16);
  };
  std::string what;
  std::set<std::string> named;
  for (const auto& l : before) {
    if (after.count(l)) continue;
    for (const auto& now : after)
      if (!before.count(now) && identity(now) == identity(l)) {
        const std::string role = l.substr(0, l.find(':'));
        const auto file = libraries.find(identity(now));
        what += (what.empty() ? "" : "; ") + ("plugin '" + role + "' (" + identity(l).substr(role.size() + 2) +
                                             (file == libraries.end() ? "" : ", " + file->second) +
                                             ") is not the library that wrote the checkpoint: its content hash is " +
                                             hash_of(now) + ", the checkpoint's " + hash_of(l) +
                                             " (rebuilt or replaced with the same version string)");
        named.insert(l);
        named.insert(now);
      }
  }
  for (const auto& l : before)
    if (!after.count(l) && !named.count(l)) what += (what.empty() ? "" : "; ") + ("the checkpoint has " + l);
  for (const auto& l : after)
    if (!before.count(l) && !named.count(l)) what += (what.empty() ? "" : "; ") + ("this run has " + l);
  return what;
}

}  // namespace

fs::path CheckpointStore::directory_for(const fs::path& output) {
  fs::path dir = output;
  dir += ".checkpoint";
  return dir;
}

CheckpointStore::CheckpointStore(fs::path dir, const std::vector<StudyCase>& cases, bool resume)
    : dir_(std::move(dir)), gdsmc_version_(version_string), pipeline_(identity_of(cases.front().pipeline.resolved_text)) {
  std::set<std::string> all;  // every case's plugins (a sweep of named variants may change them)
  std::map<std::string, std::string> libraries;  // "ROLE: NAME VERSION" -> its library file, for messages
  for (const auto& c : cases) {
    all.insert(plugin_lines(c.pipeline));
    for_each_use(c.pipeline, [&](const PluginUse& u) { libraries[use_text(u)] = u.plugin->file.string(); });
    runs_ += c.pipeline.realizations;
  }
  std::string plugins;
  for (const auto& t : all) plugins += t;
  if (resume)
    check_study(plugins, libraries);
  else
    create_study(plugins);
}

void CheckpointStore::create_study(const std::string& plugins) const {
  const fs::path study = dir_ / "study";
  std::error_code ec;
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
}

void CheckpointStore::check_study(const std::string& plugins,
                                  const std::map<std::string, std::string>& libraries) const {
  const fs::path study = dir_ / "study";
  std::error_code ec;
  if (!fs::exists(study, ec)) {
    bool runs = false;
    for (const auto& e : fs::directory_iterator(dir_, ec)) runs = runs || e.path().filename().string().rfind("run-", 0) == 0;
    if (runs)
      throw CheckpointError("--resume: the checkpoint " + dir_.string() + " is damaged: it holds run files but not " +
                            study.string() + ", which says whose runs they are; remove the directory to start over");
    throw CheckpointError("--resume: nothing to resume: there is no checkpoint at " + dir_.string() +
                          " (a run writes one there when its pipeline sets run.checkpoint)");
  }
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
    if (saved_plugins != plugins)
      differences.push_back("the plugins differ: " + plugin_differences(saved_plugins, plugins, libraries));
    if (runs != runs_ && pipeline == pipeline_)
      differences.push_back("it holds " + std::to_string(runs) + " runs, this study has " + std::to_string(runs_));
  } catch (const StateError& e) {
    throw CheckpointError("--resume: the checkpoint " + dir_.string() + " is damaged: " + study.string() +
                          " cannot be read: " + e.what() + "; remove the directory to start over");
  } catch (const CheckpointError& e) {
    if (std::string(e.what()).rfind("--resume", 0) == 0) throw;
    throw CheckpointError("--resume: the checkpoint " + dir_.string() + " is damaged: " + e.what() +
                          "; remove the directory to start over");
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
    const double tau0 = system_info(c.pipeline, c.pipeline.particles, 0).time_unit0;
    for (std::uint32_t r = 0; r < c.pipeline.realizations; ++r, ++run) {
      if (!has_run(run)) continue;
      try {
        FileStateReader in(run_file(run), Verify::tail);  // checked by check_runs (or restore)
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

std::string CheckpointStore::pipeline_identity(const std::string& resolved_text) { return identity_of(resolved_text); }

namespace {
// "run-3 and run-5", "run-0, run-1 and run-2".
std::string run_list(const std::vector<std::size_t>& runs) {
  std::string s;
  for (std::size_t k = 0; k < runs.size(); ++k)
    s += (k == 0 ? "" : k + 1 == runs.size() ? " and " : ", ") + ("run-" + std::to_string(runs[k]));
  return s;
}
}  // namespace

std::unique_ptr<Engine> CheckpointStore::read_run(std::size_t index, const StudyCase& c, std::uint32_t realization,
                                                  unsigned threads, bool restore) const {
  const fs::path file = run_file(index);
  try {
    FileStateReader r(file);
    const RunHeader h = read_run_header(r);
    if (h.format != kFormat || h.version != gdsmc_version_)
      throw CheckpointError(file.string() + " is not a run file of a gdsmc " + gdsmc_version_ + " checkpoint (it says '" +
                            h.format + "', gdsmc " + h.version + ")");
    if (h.run != index || h.realization != realization)
      throw CheckpointError(file.string() + " holds run " + std::to_string(h.run) + " (realization " +
                            std::to_string(h.realization) + "), not run " + std::to_string(index) + " (realization " +
                            std::to_string(realization) + "): files of the checkpoint were renamed or swapped");
    if (h.plugins != plugin_lines(c.pipeline))
      throw CheckpointError(file.string() + " was written with other plugins than this run's: " +
                            first_difference(h.plugins, plugin_lines(c.pipeline)));
    if (!restore) return nullptr;
    auto engine = std::make_unique<Engine>(c.pipeline, realization, threads, r);
    if (!r.at_end())
      throw CheckpointError(file.string() + ": " + std::to_string(r.remaining()) + " bytes left after the state (next entry '" +
                            r.peek_name() + "')");
    return engine;
  } catch (const StateError& e) {
    throw CheckpointError(file.string() + " cannot be read as run " + std::to_string(index) + "'s state: " + e.what());
  }
}

std::unique_ptr<Engine> CheckpointStore::restore(std::size_t index, const StudyCase& c, std::uint32_t realization,
                                                 unsigned threads) const {
  try {
    return read_run(index, c, realization, threads, true);
  } catch (const CheckpointError& e) {
    throw CheckpointError(std::string("cannot resume: ") + e.what());
  }
}

void CheckpointStore::check_runs(const std::vector<StudyCase>& cases, bool restore) const {
  std::size_t index = 0;
  for (const auto& c : cases)
    for (std::uint32_t r = 0; r < c.pipeline.realizations; ++r, ++index) {
      if (!has_run(index)) continue;
      try {
        read_run(index, c, r, 1, restore);
      } catch (const CheckpointError& e) {
        throw CheckpointError("--resume: the checkpoint " + dir_.string() + " is damaged: " + e.what() +
                              ". Remove " + run_file(index).string() +
                              " to run that run again from its start (the other runs continue from their state), "
                              "or remove the directory to start over");
      } catch (const std::exception& e) {
        throw CheckpointError("--resume: " + run_file(index).string() + " cannot be restored: " + e.what());
      }
    }
}

std::string CheckpointStore::kept_text(bool* all_kept) const {
  std::vector<std::size_t> kept, from_state, from_start;
  for (std::size_t run = 0; run < runs_; ++run) {
    bool finished = false, saved = false;
    if (has_run(run)) {
      try {
        FileStateReader in(run_file(run), Verify::tail);  // written by this process or checked when resumed
        read_run_header(in);
        finished = Engine::saved_progress(in).finished;
        saved = true;
      } catch (const std::exception&) {
      }
    }
    (finished ? kept : saved ? from_state : from_start).push_back(run);
  }
  if (all_kept) *all_kept = kept.size() == runs_;
  if (kept.size() == runs_)
    return std::string(runs_ == 1 ? "the run's results are" : "every run's results are") + " kept in " + dir_.string();
  std::string s = kept.empty() ? "no run's results are kept in " + dir_.string()
                               : "the results of " + std::to_string(kept.size()) + " of the " + std::to_string(runs_) +
                                     " runs are kept in " + dir_.string() + " (" + run_list(kept) + ")";
  std::vector<std::size_t> again = from_state;
  again.insert(again.end(), from_start.begin(), from_start.end());
  std::sort(again.begin(), again.end());
  const bool one = again.size() == 1;
  s += "; " + run_list(again) + " will run again at --resume (" +
       (one ? "its final checkpoint was" : "their final checkpoints were") + " not written)";
  const std::string its = one ? "its" : "their";
  if (!from_state.empty() && !from_start.empty())
    s += ": " + run_list(from_state) + " from " + (from_state.size() == 1 ? "its" : "their") + " last saved state, " +
         run_list(from_start) + " from " + (from_start.size() == 1 ? "its" : "their") + " start";
  else
    s += ", from " + its + (from_state.empty() ? " start" : " last saved state");
  return s;
}

void CheckpointStore::remove() const {
  std::error_code ec;
  fs::remove_all(dir_, ec);
}

}  // namespace gdsmc::host
