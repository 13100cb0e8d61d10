// Fuzzing of the shipped pipelines. A fixed-seed generator mutates every
// configs/*.yaml found at test time (so a new config is fuzzed without touching this file) and
// runs each mutation through `gdsmc validate` and a very short `gdsmc run`, as a child process in
// a fresh directory holding only the pipeline, with the output directed there (-o out.h5).
//
// Mutations (the kind cycles with the index, so every config gets every kind; the rest is drawn
// from a splitmix64 stream seeded by the base seed, the config's file name and the index, so a
// mutation does not change when configs are added): a deleted line, a duplicated line, two values
// swapped, a value replaced by another type (list, map, string, huge/tiny/negative number, 0,
// nan, inf, empty, ...), truncation at a random byte, an indentation change.
//
// Short runs without hiding bugs: `--set run.particles=200` and `--set run.stop={...: 0.2}` are
// given (to validate and run alike) only when the mutation left the pipeline's particles and
// stop entries (and the line after each) untouched; otherwise the mutated values are run as they
// are. A run then goes on for at most GDSMC_FUZZ_RUN_SECONDS (default 1) after it has installed
// its SIGINT handler, is sent SIGINT, and must exit 130 within 2 s more: every run doubles as a
// test that it can be interrupted. The SIGINT is sent only once the handler is installed (before
// that, a user's Ctrl-C ends the process by the signal, which is correct), so setup must finish
// within the hang limit (20 s). Children get RLIMIT_AS (GDSMC_FUZZ_MEMORY_MB, default 4096) so that
// a mutation asking for 1e12 particles cannot take the shared machine's memory, and no core files.
//
// Asserted for every mutation and command: exit 0, 1, or (only after our SIGINT) 130; never a
// signal or a timeout. On exit 1: a line starting "error: ", no line exposing a bare C++
// exception (std::..., yaml-cpp internals), and a last line "gdsmc: ...nothing was run or written".
// After any exit other than 0, and after validate, the directory holds only the pipeline; after a
// successful run exactly pipeline.yaml and out.h5, which HDF5 opens. A run that succeeds on a
// pipeline that validate refused is a failure too. Failures are grouped by class, each with its
// mutations (config#index, what changed, how to rerun it) and the first one in full.
//
// Environment (tests/fuzz/README.md):
//   GDSMC_FUZZ_CASES=5000        mutations in total (default 300), spread evenly over the configs
//   GDSMC_FUZZ_SEED=12345        base seed (default 20260409)
//   GDSMC_FUZZ_ONLY=hcs.yaml:17  run one mutation (and print its text)
//   GDSMC_FUZZ_JOBS=2            mutations run at once (default 2)
//   GDSMC_FUZZ_RUN_SECONDS=1     run time allowed before the SIGINT
//   GDSMC_FUZZ_MEMORY_MB=4096    the children's address-space limit
//   GDSMC_FUZZ_SAVE=DIR          write every failing mutation to DIR/<config>.<index>.yaml
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <atomic>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <set>
#include <thread>

#include "fuzz/mutations.hpp"
#include "test_support.hpp"
#include "util/text.hpp"

namespace gdsmc::test {
namespace {

// ---------------------------------------------------------------------------------------------
// Settings.

std::string env(const char* name, const std::string& fallback = "") {
  const char* v = std::getenv(name);
  return v && *v ? v : fallback;
}
double env_number(const char* name, double fallback) {
  const std::string v = env(name);
  return v.empty() ? fallback : std::stod(v);
}

constexpr std::uint64_t kDefaultSeed = 20260409;
constexpr int kDefaultCases = 300;
constexpr double kHangSeconds = 20;       // validate, or a run's setup, taking longer is a hang
// From our SIGINT to the exit: a run stops at the end of its step, or, inside a plugin call that
// does not return, when the host's watchdog fires 3 s later (kStuckCallSeconds, plugin_calls.hpp);
// 2 s more for a loaded machine to schedule the exit.
constexpr double kInterruptSeconds = 5;
const std::vector<std::string> kShortRun = {"--set", "run.particles=200", "--set", "run.stop={collisions_per_particle: 0.2}"};

// The generator: fuzz/mutations.hpp.
using namespace fuzz;

// ---------------------------------------------------------------------------------------------
// The child process.

struct Outcome {
  int exit_code = -1;
  int signal = 0;
  bool hung = false;         // validate, or a run's setup, did not end within kHangSeconds
  bool interrupted = false;  // we sent SIGINT
  bool ignored_interrupt = false;  // ... and it did not exit within kInterruptSeconds
  double seconds = 0;
  std::string out, err;
};

// Runs gdsmc with `args` in `cwd`. With `run_seconds` >= 0 the child is a run: once it catches
// SIGINT it may go on for `run_seconds`, then gets SIGINT.
Outcome run_child(const std::vector<std::string>& args, const fs::path& cwd, double run_seconds, rlim_t memory_bytes) {
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  auto pause = [] { std::this_thread::sleep_for(std::chrono::milliseconds(5)); };
  Process child(args, cwd, ProcessLimits{memory_bytes, false});  // stdout, stderr outside `cwd`
  Outcome r;
  bool done = false;
  double running_since = -1;  // when the SIGINT handler was seen
  while (!(done = child.ended())) {
    const double t = elapsed();
    if (run_seconds >= 0 && running_since < 0 && child.catches(SIGINT)) running_since = t;
    if (running_since >= 0 && t - running_since >= run_seconds) break;
    if (running_since < 0 && t >= kHangSeconds) break;
    pause();
  }
  if (!done && running_since >= 0) {
    r.interrupted = true;
    child.send(SIGINT);
    const double sent = elapsed();
    while (!(done = child.ended()) && elapsed() - sent < kInterruptSeconds) pause();
    r.ignored_interrupt = !done;
  } else if (!done) {
    r.hung = true;
  }
  const ProcessResult result = child.wait(0);  // SIGKILL if it has not ended
  r.seconds = elapsed();
  r.exit_code = result.exit_code;
  r.signal = result.timed_out ? 0 : result.signal;
  r.out = result.out;
  r.err = result.err;
  return r;
}

// ---------------------------------------------------------------------------------------------
// The checks.

std::string fmt_seconds(double s) { return host::fmt("%.1f s", s); }

std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> v;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);)
    if (!l.empty()) v.push_back(l);
  return v;
}

// Telltales of a C++ exception's what() shown to the user as it is.
const std::vector<std::string> kUnclear = {"std::", "bad_alloc", "basic_string", "_M_", "vector::", "stoi", "stod",
                                           "yaml-cpp:", "operator[]", "bad conversion", "terminate called"};

// The class of a problem with `o` for command `cmd` ("" if none); `files` is what `cwd` held after.
std::string problem(const std::string& cmd, const Outcome& o, const fs::path& cwd, const std::vector<std::string>& files,
                    std::string& detail) {
  const std::vector<std::string> only_pipeline = {"pipeline.yaml"};
  if (o.hung) return cmd + ": no exit within " + fmt_seconds(kHangSeconds) + (cmd == "run" ? " (setup never reached the step loop)" : "");
  if (o.ignored_interrupt) return cmd + ": still running " + fmt_seconds(kInterruptSeconds) + " after SIGINT";
  if (o.signal) return cmd + ": killed by signal " + std::to_string(o.signal) + " (" + strsignal(o.signal) + ")" + (o.interrupted ? " after SIGINT" : "");
  const auto lines = split(o.err);
  if (o.exit_code == 0) {
    if (cmd == "validate") {
      if (files != only_pipeline) return detail = join(files), "validate: exit 0 but left files";
      return "";
    }
    if (files != std::vector<std::string>{"out.h5", "pipeline.yaml"}) return detail = join(files), "run: exit 0 but the directory is not {out.h5, pipeline.yaml}";
    static std::mutex hdf5;  // the serial HDF5 library is not thread-safe
    const std::lock_guard<std::mutex> lock(hdf5);
    try {
      h5::File f(cwd / "out.h5");
    } catch (const std::exception& e) {
      return detail = e.what(), "run: exit 0 but out.h5 is not a readable HDF5 file";
    }
    return "";
  }
  if (o.exit_code == 130 && o.interrupted) {
    if (files != only_pipeline) return detail = join(files), "run: exit 130 after SIGINT but left files";
    return "";
  }
  if (o.exit_code != 1) return cmd + ": exit status " + std::to_string(o.exit_code) + (o.interrupted ? " after SIGINT" : "");
  if (std::none_of(lines.begin(), lines.end(), [](const std::string& l) { return l.rfind("error: ", 0) == 0; }))
    return cmd + ": exit 1 without an 'error: ' line";
  for (const auto& l : lines)
    for (const auto& u : kUnclear)
      if (l.rfind("error: ", 0) == 0 && l.find(u) != std::string::npos)
        return detail = l, cmd + ": exit 1 with an unclear message (a C++ exception's text: '" + u + "')";
  const std::string& last = lines.back();
  if (last.rfind("gdsmc: ", 0) != 0 || last.find("nothing was run or written") == std::string::npos)
    return detail = last, cmd + ": exit 1 but the last line does not say nothing was run or written";
  if (files != only_pipeline) return detail = join(files), cmd + ": exit 1 but left files";
  return "";
}

// ---------------------------------------------------------------------------------------------
// One mutation through validate and run.

struct Failure {
  std::string klass;
  const Mutation* m;
  std::string command, detail;
  Outcome outcome;
};

struct Result {
  std::vector<Failure> failures;
  std::string outcome;  // "validate <status>, run <status>", for the tally
  std::string note;     // validate accepted, run refused (allowed: run also allocates; listed)
};

std::vector<std::string> files_in(const TempDir& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::recursive_directory_iterator(dir.path())) names.push_back(fs::relative(e.path(), dir.path()).string());
  std::sort(names.begin(), names.end());
  return names;
}

std::string shell_words(const std::vector<std::string>& args) {
  std::string s = "gdsmc";
  for (const auto& a : args) s += " " + (a.find_first_of(" {}") != std::string::npos ? "'" + a + "'" : a);
  return s;
}

Result check(const Mutation& m, const std::string& original, double run_seconds, rlim_t memory) {
  Result res;
  TempDir dir;
  dir.write("pipeline.yaml", m.text);
  std::vector<std::string> extra;
  if (untouched(original, m.text, "particles") && untouched(original, m.text, "stop")) extra = kShortRun;
  extra.insert(extra.end(), {"-o", "out.h5"});
  int validate_status = -1;
  for (const std::string cmd : {"validate", "run"}) {
    std::vector<std::string> args = {cmd, "pipeline.yaml"};
    args.insert(args.end(), extra.begin(), extra.end());
    const Outcome o = run_child(args, dir.path(), cmd == "run" ? run_seconds : -1, memory);
    res.outcome += (res.outcome.empty() ? "" : ", ") + cmd + " " +
                   (o.hung || o.ignored_interrupt ? "timeout"
                    : o.signal                    ? "signal " + std::to_string(o.signal)
                    : o.interrupted               ? std::to_string(o.exit_code) + " after SIGINT"
                                                  : std::to_string(o.exit_code));
    std::string detail;
    const std::string klass = problem(cmd, o, dir.path(), files_in(dir), detail);
    if (!klass.empty()) res.failures.push_back({klass, &m, shell_words(args), detail, o});
    if (cmd == "validate") {
      validate_status = o.exit_code;
    } else if (validate_status == 1 && o.exit_code == 0) {
      res.failures.push_back({"run: exit 0 on a pipeline validate refused", &m, shell_words(args), "", o});
    } else if (validate_status == 0 && o.exit_code == 1) {
      const auto lines = split(o.err);
      res.note = m.id() + " (" + m.what + "): " + (lines.empty() ? "" : lines.front());
    }
    // Leave the directory as validate found it for the run.
    for (const auto& f : files_in(dir))
      if (f != "pipeline.yaml") fs::remove_all(dir / f);
  }
  return res;
}

std::string tail(const std::string& text, std::size_t n) {
  const auto lines = split(text);
  std::string s;
  for (std::size_t k = lines.size() > n ? lines.size() - n : 0; k < lines.size(); ++k) s += "      | " + lines[k] + "\n";
  return s;
}

// ---------------------------------------------------------------------------------------------
// The generator itself: deterministic, every kind, and mutations that do change the text.

const std::string kSample = R"(# a comment
run:
  seed: 7
  particles: 500
  time_step: {value: 0.01, unit: tau0}
  stop:
    collisions_per_particle: 2
system: {density: 1.0e-3, temperature: 1.0}
diagnostics:
  - temperature
  - {plugin: cumulants, record_every: 4}   # the fourth cumulant
output: {file: "out.h5"}
)";

TEST(FuzzGenerator, IsDeterministicAndCoversEveryKind) {
  std::set<std::string> kinds;
  for (int i = 0; i < 60; ++i) {
    const Mutation a = mutate("sample.yaml", kSample, i, kDefaultSeed), b = mutate("sample.yaml", kSample, i, kDefaultSeed);
    EXPECT_EQ(a.text, b.text) << i;
    EXPECT_EQ(a.what, b.what) << i;
    EXPECT_NE(a.text, kSample) << i << ": " << a.what;
    kinds.insert(a.kind);
  }
  EXPECT_EQ(kinds, std::set<std::string>(kKinds.begin(), kKinds.end()));
  EXPECT_NE(mutate("sample.yaml", kSample, 3, kDefaultSeed).text, mutate("sample.yaml", kSample, 3, kDefaultSeed + 1).text);
}

TEST(FuzzGenerator, FindsKeysAndValuesInBlockAndFlowStyle) {
  std::vector<std::string> keys, values;
  for (const auto& t : tokens_of(kSample)) (t.key ? keys : values).push_back(kSample.substr(t.begin, t.end - t.begin));
  EXPECT_EQ(join(keys), "run, seed, particles, time_step, value, unit, stop, collisions_per_particle, system, density, "
                        "temperature, diagnostics, plugin, record_every, output, file");
  EXPECT_EQ(join(values), "7, 500, 0.01, tau0, 2, 1.0e-3, 1.0, temperature, cumulants, 4, \"out.h5\"");
}

TEST(FuzzGenerator, ShortRunOverridesOnlyWhenParticlesAndStopAreUntouched) {
  EXPECT_TRUE(untouched(kSample, kSample, "particles"));
  EXPECT_TRUE(untouched(kSample, kSample, "stop"));
  std::string t = kSample;
  t.replace(t.find("collisions_per_particle: 2"), 26, "collisions_per_particle: .inf");
  EXPECT_FALSE(untouched(kSample, t, "stop"));   // a line under stop:
  EXPECT_TRUE(untouched(kSample, t, "particles"));
  t = kSample;
  t.insert(t.find("system:"), "    collisions_per_particle: 2\n");
  EXPECT_FALSE(untouched(kSample, t, "stop"));   // a line added at the end of the block
  t = kSample;
  t.resize(t.find("particles"));
  EXPECT_FALSE(untouched(kSample, t, "particles"));  // truncated before it
}

// ---------------------------------------------------------------------------------------------
// The fuzzing.

TEST(Fuzz, MutatedShippedPipelinesExitCleanly) {
  const auto base_seed = static_cast<std::uint64_t>(std::stoull(env("GDSMC_FUZZ_SEED", std::to_string(kDefaultSeed))));
  const int total = static_cast<int>(env_number("GDSMC_FUZZ_CASES", kDefaultCases));
  const int jobs = std::max(1, static_cast<int>(env_number("GDSMC_FUZZ_JOBS", 2)));
  const double run_seconds = env_number("GDSMC_FUZZ_RUN_SECONDS", 1);
  const auto memory = static_cast<rlim_t>(env_number("GDSMC_FUZZ_MEMORY_MB", 4096) * 1024 * 1024);
  const std::string only = env("GDSMC_FUZZ_ONLY"), save = env("GDSMC_FUZZ_SAVE");

  std::map<std::string, std::string> configs;  // file name -> text
  for (const auto& e : fs::directory_iterator(source_dir() / "configs"))
    if (e.path().extension() == ".yaml") configs[e.path().filename().string()] = read_text(e.path());
  ASSERT_FALSE(configs.empty());
  const int per_config = std::max(1, (total + static_cast<int>(configs.size()) - 1) / static_cast<int>(configs.size()));

  // Every config unmutated first (its failures are the fixture's, not the mutation's), then its mutations.
  std::vector<Mutation> mutations;
  for (const auto& [name, text] : configs)
    for (int i = -1; i < per_config; ++i) {
      Mutation m = i < 0 ? Mutation{name, -1, 0, "none", "unmutated", text} : mutate(name, text, i, base_seed);
      if (only.empty() || only == m.id()) mutations.push_back(std::move(m));
    }
  ASSERT_FALSE(mutations.empty()) << "GDSMC_FUZZ_ONLY=" << only << " names no mutation (expected <config>.yaml:<index>)";
  if (!only.empty()) std::cout << "mutation " << only << ": " << mutations[0].what << "\n" << mutations[0].text << "\n";

  std::vector<Result> results(mutations.size());
  std::atomic<std::size_t> next{0};
  const auto start = std::chrono::steady_clock::now();
  std::vector<std::thread> workers;
  for (int j = 0; j < jobs; ++j)
    workers.emplace_back([&] {
      for (std::size_t k; (k = next++) < mutations.size();)
        results[k] = check(mutations[k], configs.at(mutations[k].config), run_seconds, memory);
    });
  for (auto& w : workers) w.join();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  // Group the failures by class, in the order the classes first occur.
  std::vector<std::string> order;
  std::map<std::string, std::vector<const Failure*>> classes;
  std::vector<std::string> notes;
  std::set<const Mutation*> failing;
  std::map<std::string, int> tally;
  for (const auto& r : results) {
    ++tally[r.outcome];
    for (const auto& f : r.failures) {
      if (!classes.count(f.klass)) order.push_back(f.klass);
      classes[f.klass].push_back(&f);
      failing.insert(f.m);
    }
    if (!r.note.empty()) notes.push_back(r.note);
  }
  std::printf("fuzz: %zu pipelines (%d mutations each + unmutated), seed %" PRIu64 ", %d jobs: %zu runs in %.1f s; "
              "%zu of them failing in %zu class(es)\n",
              configs.size(), per_config, base_seed, jobs, mutations.size(), wall, failing.size(), order.size());
  for (const auto& [outcome, count] : tally) std::printf("  %4d x %s\n", count, outcome.c_str());
  if (!notes.empty()) {
    std::printf("fuzz: %zu mutations passed validate and were refused by run (allowed; first ones):\n", notes.size());
    for (std::size_t k = 0; k < std::min<std::size_t>(notes.size(), 10); ++k) std::printf("  %s\n", notes[k].c_str());
  }
  if (!save.empty()) {
    fs::create_directories(save);
    for (const Mutation* m : failing)
      std::ofstream(fs::path(save) / (m->config + "." + std::to_string(m->index) + ".yaml"), std::ios::binary) << m->text;
  }
  for (const auto& klass : order) {
    const auto& list = classes[klass];
    std::ostringstream s;
    s << "[" << list.size() << " mutation" << (list.size() == 1 ? "" : "s") << "] " << klass << "\n";
    for (std::size_t k = 0; k < list.size() && k < 25; ++k) {
      const Failure& f = *list[k];
      s << "  " << f.m->id() << "  " << f.m->kind << ": " << f.m->what << (f.detail.empty() ? "" : "  -> " + f.detail) << "\n";
    }
    if (list.size() > 25) s << "  ... and " << list.size() - 25 << " more\n";
    const Failure& f = *list.front();
    s << "  first one in full (rerun: GDSMC_FUZZ_ONLY=" << f.m->id() << " GDSMC_FUZZ_SEED=" << base_seed
      << " tests/fuzz/fuzz_test; seed of the mutation " << f.m->seed << "):\n    $ " << f.command << "\n    exit "
      << f.outcome.exit_code << (f.outcome.signal ? ", signal " + std::to_string(f.outcome.signal) : "")
      << (f.outcome.interrupted ? ", SIGINT sent" : "") << ", " << fmt_seconds(f.outcome.seconds) << "; stderr (end):\n"
      << tail(f.outcome.err, 6) << "    pipeline.yaml:\n";
    for (const auto& l : split(f.m->text)) s << "      " << l << "\n";
    ADD_FAILURE() << s.str();
  }
}

// Damaged checkpoints: a checkpoint of two finished runs (kept because the output could not be
// written: a file size limit above each run file and below the output), then, one at a time,
// every run file cut at random bytes, random bits flipped anywhere in a file (entries, the table
// of checksums, its tail), the two run files swapped, a run file replaced by the study file or
// emptied, and the study file damaged. `validate --resume` and `run --resume` must each refuse
// every one with exit 1, an `error:` line naming the file, and nothing written; the checkpoint as
// it was then resumes to the bits of the uninterrupted run.
TEST(Fuzz, DamagedCheckpointsAreRefusedNamingTheFile) {
  const auto base_seed = static_cast<std::uint64_t>(std::stoull(env("GDSMC_FUZZ_SEED", std::to_string(kDefaultSeed))));
  TempDir dir;
  const fs::path pipeline = dir.write(
      "pipeline.yaml",
      "run:\n  seed: 5\n  particles: 2000\n  realizations: 2\n"
      "  time_step: {value: 0.01, unit: tau0, follow_temperature: true}\n  stop: {collisions_per_particle: 2}\n"
      "  record_every: 10\n  checkpoint: {every: {collisions_per_particle: 0.5}}\n"
      "system: {density: 1.0e-3, temperature: 1.0}\ninitial_state: maxwellian\n"
      "collision: {plugin: inelastic_hard_spheres, alpha: 0.7}\n"
      "diagnostics: [temperature, cumulants, velocity_marginals]\noutput: {file: out.h5, realizations: true}\n");
  ProcessResult ref = run_gdsmc({"run", pipeline.string(), "--quiet", "--threads", "1", "-o", "ref.h5"}, dir.path());
  ASSERT_EQ(ref.exit_code, 0) << ref.describe();
  // dash counts 512-byte blocks: 60 KiB, above each finished run's file (~30 KB), below the output (~200 KB).
  const ShellResult kept = shell("cd '" + dir.path().string() + "' && ulimit -f 120 && exec '" + executable().string() +
                                 "' run pipeline.yaml --quiet --threads 1");
  ASSERT_NE(kept.status, 0) << kept.out;
  ASSERT_TRUE(contains(kept.out, "every run's results are kept in out.h5.checkpoint")) << kept.out;
  const fs::path ck = dir / "out.h5.checkpoint";
  const std::map<std::string, std::string> originals{
      {"run-0", read_text(ck / "run-0")}, {"run-1", read_text(ck / "run-1")}, {"study", read_text(ck / "study")}};

  struct Damage {
    std::string what, file;                      // what was done; the file the message must name
    std::map<std::string, std::string> contents;  // the files as damaged
  };
  std::vector<Damage> damages;
  std::uint64_t state = mutation_seed(base_seed, "checkpoint", 0);
  auto next = [&](std::uint64_t n) {  // splitmix64
    state += 0x9E3779B97F4A7C15ull;
    std::uint64_t z = state;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return (z ^ (z >> 31)) % n;
  };
  for (const std::string file : {"run-0", "run-1", "study"}) {
    const std::string& bytes = originals.at(file);
    for (int k = 0; k < 6; ++k) {  // cut short
      const std::size_t at = k == 0 ? 0 : k == 1 ? bytes.size() - 1 : next(bytes.size());
      Damage d{file + " cut at byte " + std::to_string(at), file, originals};
      d.contents[file] = bytes.substr(0, at);
      damages.push_back(std::move(d));
    }
    for (int k = 0; k < (file == "study" ? 6 : 12); ++k) {  // bits flipped: anywhere, then in the last 64 bytes
      const std::size_t at = k < 8 ? next(bytes.size()) : bytes.size() - 1 - next(std::min<std::size_t>(64, bytes.size()));
      const int bit = static_cast<int>(next(8));
      Damage d{file + " bit " + std::to_string(bit) + " of byte " + std::to_string(at) + " flipped", file, originals};
      d.contents[file][at] = static_cast<char>(d.contents[file][at] ^ (1 << bit));
      damages.push_back(std::move(d));
    }
  }
  {
    Damage d{"run-0 and run-1 swapped", "run-0", originals};
    std::swap(d.contents["run-0"], d.contents["run-1"]);
    damages.push_back(std::move(d));
    Damage s{"run-1 replaced by the study file", "run-1", originals};
    s.contents["run-1"] = originals.at("study");
    damages.push_back(std::move(s));
    Damage e{"run-0 emptied", "run-0", originals};
    e.contents["run-0"].clear();
    damages.push_back(std::move(e));
  }

  std::vector<std::string> failures;
  for (const Damage& d : damages) {
    for (const auto& [name, bytes] : d.contents) std::ofstream(ck / name, std::ios::binary | std::ios::trunc) << bytes;
    for (const std::string command : {"validate", "run"}) {
      const ProcessResult r = run_gdsmc({command, pipeline.string(), "--resume", "--quiet", "--threads", "1"}, dir.path());
      std::string why;
      if (r.exit_code != 1) why = "exit " + std::to_string(r.exit_code) + (r.signal ? " (signal)" : "");
      else if (!contains(r.err, "error: ")) why = "no error line";
      else if (!contains(r.err, "out.h5.checkpoint/" + d.file)) why = "the message does not name " + d.file;
      else if (fs::exists(dir / "out.h5")) why = "an output was written";
      if (!why.empty()) failures.push_back(command + ", " + d.what + ": " + why + "\n" + tail(r.err, 600));
    }
  }
  EXPECT_TRUE(failures.empty()) << failures.size() << " of " << 2 * damages.size() << " refusals wrong; the first:\n"
                                << (failures.empty() ? "" : failures.front());
  for (const auto& [name, bytes] : originals) std::ofstream(ck / name, std::ios::binary | std::ios::trunc) << bytes;
  const ProcessResult r = run_gdsmc({"run", pipeline.string(), "--resume", "--quiet"}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << "the undamaged checkpoint resumes\n" << r.describe();
  const auto expected = h5::contents(dir / "ref.h5"), got = h5::contents(dir / "out.h5");
  ASSERT_EQ(got.size(), expected.size());
  for (const auto& [key, bytes] : expected) EXPECT_TRUE(got.count(key) && got.at(key) == bytes) << key;
}

}  // namespace
}  // namespace gdsmc::test
