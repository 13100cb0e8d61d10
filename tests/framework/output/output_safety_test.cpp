// Output safety: a failed write exits 1 with one message saying the results are lost;
// output paths are checked before the first step (run and validate alike); gdsmc writes over
// nothing that is not its output (devices, pipes, directories, the pipeline, plugin libraries)
// and says what it replaces; temporaries are named so users recognise them, removed on failure
// or Ctrl-C, cleaned up after a killed run, and never someone else's; the final particles are
// written from the particle store without a second copy; option prefixes are refused.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>
#include <thread>
#include <vector>

#include "app/cli.hpp"
#include "config/system_info.hpp"
#include "conformance/conformance.hpp"
#include "output/hdf5_file.hpp"
#include "output/output_path.hpp"
#include "output/particle_dump.hpp"
#include "test_support.hpp"

namespace {

using namespace gdsmc::test;
namespace host = gdsmc::host;

// A short homogeneous run (N = 500, s = 2), or with kLongStop one that takes far longer than any
// test waits (elastic, N = 20000 to s = 1e5): a check made "before the run" must answer at once.
const std::string kLongStop = "{collisions_per_particle: 100000}";
std::string pipeline_yaml(const std::string& stop = "{collisions_per_particle: 2}", int particles = 500,
                          const std::string& output = "{file: out.h5}", const std::string& extra_diagnostics = "") {
  const bool long_run = stop == kLongStop;
  return "run:\n"
         "  seed: 5\n"
         "  particles: " + std::to_string(long_run ? 20000 : particles) + "\n"
         "  time_step: {value: 0.01, unit: tau0, follow_temperature: true}\n"
         "  stop: " + stop + "\n"
         "  sample_every: 5\n"
         "  record_every: 10\n"
         "system:\n"
         "  density: 1.0e-3\n"
         "  temperature: 1.0\n"
         "initial_state: {plugin: maxwellian}\n"
         "collision: {plugin: inelastic_hard_spheres, alpha: " + std::string(long_run ? "1.0" : "0.8") + "}\n"
         "diagnostics:\n"
         "  - {plugin: temperature}\n"
         "  - {plugin: cumulants}\n" + extra_diagnostics +
         "output: " + output + "\n";
}

std::string host_name() {
  char buf[256] = {};
  ::gethostname(buf, sizeof buf - 1);
  return buf;
}
std::string pid_namespace() {
  char link[128] = {};
  const ssize_t n = ::readlink("/proc/self/ns/pid", link, sizeof link - 1);
  std::string digits;
  for (ssize_t k = 0; k < n; ++k)
    if (link[k] >= '0' && link[k] <= '9') digits += link[k];
  return digits;
}
// A PID that no process has: a child that has exited and been reaped.
pid_t dead_pid() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  int status = 0;
  ::waitpid(child, &status, 0);
  return child;
}
// The temporary files of out.h5 in `dir`: ".out.h5.gdsmc-partial-HOST-NS-PID-XXXXXX".
std::vector<std::string> temporaries(const fs::path& dir, const std::string& name = "out.h5") {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string n = e.path().filename().string();
    if (n.rfind("." + name + ".gdsmc-partial-", 0) == 0) out.push_back(n);
  }
  return out;
}
bool is_hdf5(const fs::path& p) { return fs::is_regular_file(p) && read_text(p).rfind("\x89HDF\r\n\x1a\n", 0) == 0; }
// The names in `dir` (links not followed).
std::vector<std::string> names(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}
int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

// ---------------------------------------------------------------------------------------------
// 1. A write failure never crashes and never loses the run silently.

// A file size limit (ulimit -f: dash counts 512-byte blocks) makes the final write fail, with
// SIGXFSZ ignored by the caller and with it at its default (gdsmc must not be killed by it):
// exit 1 (not a SIGSEGV in HDF5's clean-up at exit), one line saying the results are lost,
// no temporary file left. The particles (written as the run ends) fail the same way.
TEST(OutputSafety, AWriteFailureExitsOneWithOneMessageAndRemovesTheTemporaryFile) {
  struct Case {
    std::string name, trap, yaml;
  };
  const std::vector<Case> cases = {
      {"SIGXFSZ ignored", "trap '' XFSZ; ", pipeline_yaml()},
      {"SIGXFSZ default", "", pipeline_yaml()},
      {"particles", "", pipeline_yaml("{collisions_per_particle: 0.5}", 20000, "{file: out.h5, particles: true}")}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    TempDir dir;
    dir.write("pipeline.yaml", c.yaml);
    const ShellResult r = shell("cd '" + dir.path().string() + "' && (" + c.trap + "ulimit -f 16; exec '" +
                                executable().string() + "' run pipeline.yaml --quiet)");
    EXPECT_EQ(r.status, 1) << r.out;
    EXPECT_TRUE(contains(r.out, "cannot write out.h5")) << r.out;
    EXPECT_TRUE(contains(r.out, "File too large")) << r.out;
    EXPECT_TRUE(contains(r.out, "are lost")) << r.out;
    EXPECT_EQ(count_lines(r.out), 1) << r.out;
    EXPECT_EQ(dir.entries_except({"pipeline.yaml"}), std::vector<std::string>{});
  }
}

// 10. A Ctrl-C when the computation is over and the file is being written (the test plugin
// raises SIGINT in finish(), the last plugin call of the run): exit 130, nothing written, the
// temporary file removed.
TEST(OutputSafety, CtrlCDuringTheFinalWriteAbortsIt) {
  for (const std::string output : {"{file: out.h5}", "{file: out.h5, particles: true}"}) {
    SCOPED_TRACE(output);
    TempDir dir;
    const auto file = dir.write("pipeline.yaml", pipeline_yaml("{collisions_per_particle: 1}", 500, output,
                                                               "  - {plugin: interrupt_at_finish}\n"));
    const ProcessResult r = run_gdsmc(
        {"run", file.string(), "--quiet", "--plugin-path", test_plugin("interrupt_at_finish").string()}, dir.path(), 60);
    EXPECT_EQ(r.exit_code, 130) << r.describe();
    EXPECT_TRUE(contains(r.err, "interrupted")) << r.describe();
    EXPECT_EQ(dir.entries_except({"pipeline.yaml"}), std::vector<std::string>{});
  }
}

// ---------------------------------------------------------------------------------------------
// 2. Output paths are checked before the run (and by validate), with the option or the pipeline
// line that gave them.

TEST(OutputSafety, UnwritableOutputPathsAreRefusedBeforeTheRun) {
  TempDir dir;
  const auto file = dir.write("pipeline.yaml", pipeline_yaml(kLongStop));
  fs::create_directory(dir / "d");
  dir.write("plain.txt", "text\n");
  struct Case {
    std::string output, says;
  };
  const std::vector<Case> cases = {
      {"d", "is a directory"},
      {".", "names a directory"},
      {"d/", "names a directory"},
      {"..", "names a directory"},
      {std::string(300, 'a') + ".h5", "bytes long; the filesystem"},
      {"missing/out.h5", "does not exist"},
      {"plain.txt/out.h5", "is not a directory"},
      {"/proc/gdsmc-output-test.h5", "cannot create a file in '/proc'"},  // unwritable, even for root
  };
  for (const auto& c : cases) {
    for (const std::string command : {"run", "validate"}) {
      SCOPED_TRACE(command + " --output " + c.output.substr(0, 40));
      const ProcessResult r = run_gdsmc({command, file.string(), "--quiet", "--output", c.output}, dir.path(), 30);
      EXPECT_FALSE(r.timed_out) << "the path was not checked before the run";
      EXPECT_EQ(r.exit_code, 1) << r.describe();
      EXPECT_TRUE(contains(r.err, "error: --output " + c.output + ": ")) << r.describe();
      EXPECT_TRUE(contains(r.err, c.says)) << r.describe();
      EXPECT_TRUE(contains(r.err, "nothing was run or written")) << r.describe();
      EXPECT_EQ(dir.entries_except({"pipeline.yaml", "d", "plain.txt"}), std::vector<std::string>{});
    }
  }
  // From the pipeline: located at output.file's line.
  const auto in_file = dir.write("in_file.yaml", pipeline_yaml(kLongStop, 0, "{file: d}"));
  const ProcessResult r = run_gdsmc({"run", in_file.string(), "--quiet"}, dir.path(), 30);
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, in_file.string() + ":" + std::to_string(line_of(read_text(in_file), "output:")) +
                                  ":16: output.file: 'd' is a directory"))
      << r.describe();
}

// An empty --output, and an output.file that is empty, null, a list or a mapping, are refused
// (they used to fall back to the default name).
TEST(OutputSafety, EmptyOrNonScalarOutputNamesAreRefused) {
  TempDir dir;
  const auto file = dir.write("pipeline.yaml", pipeline_yaml());
  for (const std::vector<std::string> args : {std::vector<std::string>{"--output", ""}, {"--output="}, {"-o", ""}}) {
    std::vector<std::string> argv{"run", file.string(), "--quiet"};
    argv.insert(argv.end(), args.begin(), args.end());
    const ProcessResult r = run_gdsmc(argv, dir.path());
    EXPECT_EQ(r.exit_code, 2) << r.describe();
    EXPECT_TRUE(contains(r.err, "--output needs a file name")) << r.describe();
  }
  struct Case {
    std::string file, says;
  };
  for (const Case& c : {Case{"[a.h5, b.h5]", "a list"}, Case{"{name: a.h5}", "a mapping"}, Case{"\"\"", "an empty name"},
                        Case{"", "nothing"}}) {
    SCOPED_TRACE(c.file);
    const auto bad = dir.write("bad.yaml", pipeline_yaml("{collisions_per_particle: 2}", 500, "{file: " + c.file + "}"));
    for (const std::string command : {"run", "validate"}) {
      const ProcessResult r = run_gdsmc({command, bad.string(), "--quiet"}, dir.path());
      EXPECT_EQ(r.exit_code, 1) << r.describe();
      EXPECT_TRUE(contains(r.err, bad.string() + ":" + std::to_string(line_of(read_text(bad), "output:")) + ":"))
          << r.describe();
      EXPECT_TRUE(contains(r.err, "output.file: expected a file name such as NAME.h5, got " + c.says)) << r.describe();
    }
  }
  EXPECT_EQ(dir.entries_except({"pipeline.yaml", "bad.yaml"}), std::vector<std::string>{});
}

// ---------------------------------------------------------------------------------------------
// 3. gdsmc never destroys what is not its output.

TEST(OutputSafety, WhatIsNotAnOutputIsNeverWrittenOver) {
  TempDir dir;
  // A copy of a test plugin, used by the pipeline and named as the output.
  const fs::path library = dir / "gdsmc_failing_finish.so";
  fs::copy_file(test_plugin("failing_finish"), library);
  const std::string library_bytes = read_text(library);
  const auto file = dir.write("pipeline.yaml", pipeline_yaml(kLongStop, 0, "{file: out.h5}", "  - {plugin: failing_finish}\n"));
  const std::string pipeline_text = read_text(file);
  ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0644), 0);
  const bool device = ::mknod((dir / "null").c_str(), S_IFCHR | 0666, makedev(1, 3)) == 0;  // needs root
  fs::create_symlink("pipeline.yaml", dir / "link.yaml");
  struct Case {
    std::string output, says;
  };
  std::vector<Case> cases = {{"fifo", "'fifo' is a named pipe"},
                             {"pipeline.yaml", "'pipeline.yaml' is the pipeline"},
                             {file.string(), "is the pipeline"},
                             {"link.yaml", "'link.yaml' links to the pipeline"},
                             {library.string(), "is the library of plugin 'failing_finish'"}};
  if (device) cases.push_back({"null", "'null' is a character device"});
  for (const auto& c : cases) {
    for (const std::string command : {"run", "validate"}) {
      SCOPED_TRACE(command + " --output " + c.output);
      const ProcessResult r = run_gdsmc({command, file.string(), "--quiet", "--plugin-path", library.string(), "--output", c.output},
                                        dir.path(), 30);
      EXPECT_FALSE(r.timed_out);
      EXPECT_EQ(r.exit_code, 1) << r.describe();
      EXPECT_TRUE(contains(r.err, "error: --output " + c.output + ": ")) << r.describe();
      EXPECT_TRUE(contains(r.err, c.says)) << r.describe();
    }
  }
  struct stat st;
  ASSERT_EQ(::lstat((dir / "fifo").c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode));
  if (device) {
    ASSERT_EQ(::lstat((dir / "null").c_str(), &st), 0);
    EXPECT_TRUE(S_ISCHR(st.st_mode));
  }
  EXPECT_TRUE(fs::is_symlink(dir / "link.yaml"));
  EXPECT_EQ(read_text(file), pipeline_text);
  EXPECT_EQ(read_text(library), library_bytes);
  EXPECT_TRUE(temporaries(dir.path(), "fifo").empty());
}

// An existing file is replaced with one line on stderr saying so; a symbolic link is replaced
// itself (its target is left as it is), and the line names the target; validate says what a run
// would replace and touches nothing.
TEST(OutputSafety, ReplacingAFileOrALinkIsAnnounced) {
  TempDir dir;
  const auto file = dir.write("pipeline.yaml", pipeline_yaml());
  dir.write("out.h5", "an older result\n");
  dir.write("target.h5", "the link's target\n");
  fs::create_symlink("target.h5", dir / "link.h5");

  const ProcessResult v = run_gdsmc({"validate", file.string()}, dir.path());
  EXPECT_EQ(v.exit_code, 0) << v.describe();
  EXPECT_TRUE(contains(v.err, "gdsmc: out.h5 exists: a run would replace it")) << v.describe();
  EXPECT_EQ(read_text(dir / "out.h5"), "an older result\n");
  const ProcessResult vl = run_gdsmc({"validate", file.string(), "-o", "link.h5"}, dir.path());
  EXPECT_EQ(vl.exit_code, 0) << vl.describe();
  EXPECT_TRUE(contains(vl.err, "link.h5 is a symbolic link to target.h5: a run would replace the link (not target.h5)"))
      << vl.describe();
  EXPECT_TRUE(fs::is_symlink(dir / "link.h5"));
  EXPECT_EQ(names(dir.path()), (std::vector<std::string>{"link.h5", "out.h5", "pipeline.yaml", "target.h5"}));

  const ProcessResult r = run_gdsmc({"run", file.string(), "--quiet"}, dir.path());
  EXPECT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_EQ(r.err, "gdsmc: replacing existing out.h5 when the run completes\n") << r.describe();
  EXPECT_TRUE(is_hdf5(dir / "out.h5"));

  const ProcessResult rl = run_gdsmc({"run", file.string(), "--quiet", "-o", "link.h5"}, dir.path());
  EXPECT_EQ(rl.exit_code, 0) << rl.describe();
  EXPECT_EQ(rl.err, "gdsmc: link.h5 is a symbolic link to target.h5: the run replaces the link (not target.h5) with its output\n")
      << rl.describe();
  EXPECT_FALSE(fs::is_symlink(dir / "link.h5"));
  EXPECT_TRUE(is_hdf5(dir / "link.h5"));
  EXPECT_EQ(read_text(dir / "target.h5"), "the link's target\n");
  EXPECT_EQ(names(dir.path()), (std::vector<std::string>{"link.h5", "out.h5", "pipeline.yaml", "target.h5"}));
}

// The temporary file exists from before the first step under a name users can recognise
// (".out.h5.gdsmc-partial-HOST-NS-PID-XXXXXX"); SIGKILL leaves it, and the next run with the
// same output removes it (its process is gone) and says so.
TEST(OutputSafety, AKilledRunsTemporaryFileIsRemovedByTheNextRun) {
  TempDir dir;
  const auto long_run = dir.write("long.yaml", pipeline_yaml(kLongStop));
  std::vector<std::string> tmp;
  {
    Process p({"run", long_run.string(), "--quiet"}, dir.path());
    ASSERT_TRUE(p.wait_until_catches(SIGINT));
    for (int k = 0; k < 3000 && tmp.empty(); ++k) {
      tmp = temporaries(dir.path());
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ASSERT_EQ(tmp.size(), 1u);
    const std::string prefix = ".out.h5.gdsmc-partial-" + host_name() + "-" + pid_namespace() + "-";
    ASSERT_EQ(tmp[0].rfind(prefix, 0), 0u) << tmp[0];
    const std::string rest = tmp[0].substr(prefix.size());  // PID-XXXXXX
    ASSERT_EQ(rest.size() - rest.find('-'), 7u) << tmp[0];
    p.send(SIGKILL);
    EXPECT_EQ(p.wait(30).signal, SIGKILL);
  }
  EXPECT_EQ(temporaries(dir.path()), tmp);
  const auto file = dir.write("pipeline.yaml", pipeline_yaml());
  const ProcessResult r = run_gdsmc({"run", file.string(), "--quiet"}, dir.path());
  EXPECT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_TRUE(contains(r.err, "gdsmc: removed " + tmp[0] + ", left by gdsmc process ")) << r.describe();
  EXPECT_EQ(dir.entries_except({}), (std::vector<std::string>{"long.yaml", "out.h5", "pipeline.yaml"}));
}

// Stale temporaries are removed only when they provably belong to a gdsmc process of this host
// and PID namespace that no longer runs: never another host's, another namespace's, a live
// process's, another output's, another user's, or anything that is not a regular file.
TEST(OutputSafety, OnlyProvablyStaleTemporariesAreRemoved) {
  TempDir dir;
  const auto file = dir.write("pipeline.yaml", pipeline_yaml());
  const std::string host = host_name(), ns = pid_namespace(), dead = std::to_string(dead_pid());
  ASSERT_FALSE(ns.empty());
  const std::string prefix = ".out.h5.gdsmc-partial-";
  const std::string stale = prefix + host + "-" + ns + "-" + dead + "-aB3dE9";
  const std::vector<std::string> kept = {
      prefix + host + "-" + ns + "-" + std::to_string(::getpid()) + "-aB3dE9",  // alive (this test)
      prefix + "another-host-" + ns + "-" + dead + "-aB3dE9",
      prefix + host + "-1" + ns + "-" + dead + "-aB3dE9",                       // another PID namespace
      ".other.h5.gdsmc-partial-" + host + "-" + ns + "-" + dead + "-aB3dE9",  // another output's
      prefix + host + "-" + ns + "-" + dead + "-short",                       // not a name gdsmc makes
      "out.h5.partial-" + dead,                                               // not gdsmc's pattern
  };
  dir.write(stale, "stale");
  for (const auto& k : kept) dir.write(k, "kept");
  const std::string others = prefix + host + "-" + ns + "-" + dead + "-Xy7Zw1";  // another user's
  dir.write(others, "kept");
  const bool chowned = ::chown((dir / others).c_str(), 65534, 65534) == 0 && ::geteuid() != 65534;
  fs::create_directory(dir / (prefix + host + "-" + ns + "-" + dead + "-dIrEcT"));

  const ProcessResult r = run_gdsmc({"run", file.string(), "--quiet"}, dir.path());
  EXPECT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_FALSE(fs::exists(dir / stale)) << r.describe();
  EXPECT_TRUE(contains(r.err, "gdsmc: removed " + stale + ", left by gdsmc process " + dead + " of this host")) << r.describe();
  for (const auto& k : kept) EXPECT_EQ(read_text(dir / k), "kept") << k;
  if (chowned) EXPECT_TRUE(fs::exists(dir / others));
  EXPECT_TRUE(fs::is_directory(dir / (prefix + host + "-" + ns + "-" + dead + "-dIrEcT")));
}

// The temporary file: created with a fresh name each time (never an existing one), and removed
// only while its name still refers to the file it created.
TEST(OutputSafety, TemporaryFilesNeverCollideAndRemoveOnlyTheirOwnFile) {
  TempDir dir;
  const host::OutputTarget target = host::check_output_path(dir / "out.h5", {});
  host::TemporaryFile a(target), b(target);
  EXPECT_NE(a.path(), b.path());
  EXPECT_EQ(a.path().parent_path(), dir.path());
  EXPECT_EQ(a.path().filename().string().rfind(".out.h5.gdsmc-partial-", 0), 0u) << a.path();
  // Another file takes a's name (another process, a user): a leaves it alone.
  const fs::path other = dir.write("other", "not gdsmc's");
  fs::rename(other, a.path());
  a.remove();
  EXPECT_EQ(read_text(a.path()), "not gdsmc's");
  b.remove();
  EXPECT_FALSE(fs::exists(b.path()));
}

// ---------------------------------------------------------------------------------------------
// 7. The final particles are written from the particle store, not from a second full copy: with
// the run's file open, the case output holds no particle data, and the file holds the store's
// values scaled exactly as before (sqrt(2T0/m)). A homogeneous system keeps no positions: the
// velocities alone are written.
TEST(OutputSafety, ParticlesAreWrittenFromTheStoreWithoutACopy) {
  TempDir dir;
  const host::Pipeline p = load_yaml(dir, pipeline_yaml("{collisions_per_particle: 0.5}", 300000, "{file: out.h5, particles: true}"));
  host::OutputFile out(host::check_output_path(dir / "out.h5", {}));
  host::Engine engine(p);
  engine.run();
  host::StudyOutput study;
  const host::ParticleStager stager = out.stager();
  study.cases.push_back(engine.output(&stager));
  ASSERT_EQ(study.cases[0].particles.size(), 3u);
  for (const auto& d : study.cases[0].particles) {
    EXPECT_TRUE(d.data.empty()) << d.name << ": a copy of the particles was held in memory";
    EXPECT_FALSE(d.staged.empty()) << d.name;
  }
  out.commit(study);
  const gdsmc::ParticleSpan s = engine.particles();
  const gdsmc::SystemInfo system = host::system_info(p, p.particles, 0);
  h5::File f(dir / "out.h5");
  EXPECT_FALSE(h5::exists(f.id(), "/particles/x"));
  const auto vx = h5::read_doubles(f.id(), "/particles/vx");
  const auto vz = h5::read_doubles(f.id(), "/particles/vz");
  ASSERT_EQ(vx.size(), s.count);
  ASSERT_EQ(vz.size(), s.count);
  const double speed = std::sqrt(2.0 * system.initial_temperature / system.mass);
  std::size_t wrong = 0;
  for (std::size_t i = 0; i < s.count; ++i)
    wrong += vx[i] != s.vx[i] / speed || vz[i] != s.vz[i] / speed;
  EXPECT_EQ(wrong, 0u);
  EXPECT_FALSE(h5::exists(f.id(), "/.gdsmc-staging"));
  EXPECT_EQ(dir.entries_except({"pipeline.yaml"}), std::vector<std::string>{"out.h5"});
}

// The interrupt flag stops the writing (commit, and the particles written as the run ends) and
// the temporary file is removed.
TEST(OutputSafety, TheInterruptFlagStopsTheWriting) {
  TempDir dir;
  std::atomic<bool> interrupted{true};
  const host::Pipeline p = load_yaml(dir, pipeline_yaml("{collisions_per_particle: 0.2}", 500, "{file: out.h5, particles: true}"));
  {
    host::OutputFile out(host::check_output_path(dir / "out.h5", {}), &interrupted);
    EXPECT_EQ(temporaries(dir.path()).size(), 1u);
    host::Engine engine(p);
    engine.run();
    const host::ParticleStager stager = out.stager();
    EXPECT_THROW(engine.output(&stager), host::OutputInterrupted);
    EXPECT_THROW(out.commit(host::StudyOutput{}), host::OutputInterrupted);
  }
  EXPECT_EQ(dir.entries_except({"pipeline.yaml"}), std::vector<std::string>{});
}

// ---------------------------------------------------------------------------------------------
// 10. Option prefixes and extensions are not taken for options (--settings is not --set,
// --output-dir is not --output), in every command that takes options: every option of every
// table through the parsers themselves, and the reported cases through the executable.
// What the command's parser says of `words` ("" when it accepts them).
std::string parse_error(const std::string& command, std::vector<std::string> words) {
  words.insert(words.begin(), command);
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  if (command == "conformance") {
    ::testing::internal::CaptureStderr();
    ::testing::internal::CaptureStdout();
    gdsmc::host::run_conformance(static_cast<int>(words.size()), argv.data());
    ::testing::internal::GetCapturedStdout();
    return ::testing::internal::GetCapturedStderr();
  }
  host::Options o;
  std::string error;
  return host::parse(command, static_cast<int>(words.size()), argv.data(), 1, o, error) ? "" : error;
}

TEST(OutputSafety, OptionPrefixesAreRefused) {
  std::vector<std::pair<std::string, std::vector<std::string>>> commands;
  for (const std::string command : {"run", "validate", "plugins"}) {
    std::vector<std::string> names;
    for (const auto& spec : host::command_options(command))
      for (const auto& n : spec.names)
        if (n.rfind("--", 0) == 0) names.push_back(n);
    ASSERT_FALSE(names.empty()) << command;
    commands.emplace_back(command, names);
  }
  commands.emplace_back("conformance", std::vector<std::string>{"--params", "--context", "--seed", "--timeout", "--only",
                                                                "--plugin-path", "--list", "--no-fork", "--help"});
  for (const auto& [command, names] : commands)
    for (const auto& name : names) {
      EXPECT_FALSE(contains(parse_error(command, {name, "1"}), "unknown option")) << command << " refuses " << name;
      for (const std::string& wrong : {name.substr(0, name.size() - 1), name + "s", name + "-dir"}) {
        EXPECT_TRUE(contains(parse_error(command, {wrong, "x"}), "unknown option '" + wrong + "'")) << command << " " << wrong;
        EXPECT_TRUE(contains(parse_error(command, {wrong + "=x"}), "unknown option '" + wrong + "=x'")) << command << " " << wrong;
      }
    }
  TempDir dir;
  const auto file = dir.write("pipeline.yaml", pipeline_yaml());
  const std::vector<std::pair<std::vector<std::string>, std::string>> reported = {
      {{"run", file.string(), "--settings", "run.particles=100"}, "--settings"},
      {{"run", file.string(), "--output-dir", "x"}, "--output-dir"},
      {{"validate", file.string(), "--settings=run.particles=100"}, "--settings=run.particles=100"},
      {{"validate", file.string(), "--output-dir=x"}, "--output-dir=x"},
      {{"plugins", "--plugin", "x"}, "--plugin"},
      {{"conformance", test_plugin("failing_finish").string(), "--param", "x"}, "--param"}};
  for (const auto& [args, option] : reported) {
    const ProcessResult r = run_gdsmc(args, dir.path(), 30);
    EXPECT_EQ(r.exit_code, 2) << r.describe();
    EXPECT_TRUE(contains(r.err, "unknown option '" + option + "'")) << r.describe();
  }
  EXPECT_EQ(dir.entries_except({"pipeline.yaml"}), std::vector<std::string>{});
}

// Two runs writing one output at once both exited 0, and the first run's results were silently
// replaced. The output's lock (".out.h5.gdsmc-lock", flock) is held while a run writes: a second
// run with the same output is refused at start naming the first, while a run with another output
// in the same directory goes on; the lock is removed when the run ends (interrupted too), and one
// left by a killed run (no live holder) blocks nothing and is removed.
TEST(OutputSafety, ASecondRunWritingTheSameOutputIsRefusedWhileTheFirstLives) {
  TempDir dir;
  const auto long_run = dir.write("long.yaml", pipeline_yaml(kLongStop));
  const auto file = dir.write("pipeline.yaml", pipeline_yaml());
  {
    Process first({"run", long_run.string(), "--quiet"}, dir.path());
    ASSERT_TRUE(first.wait_until_catches(SIGINT));
    for (int k = 0; k < 3000 && temporaries(dir.path()).empty(); ++k)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    ASSERT_EQ(temporaries(dir.path()).size(), 1u);
    EXPECT_TRUE(fs::exists(dir / ".out.h5.gdsmc-lock"));
    const ProcessResult second = run_gdsmc({"run", file.string(), "--quiet"}, dir.path());
    EXPECT_EQ(second.exit_code, 1) << second.describe();
    EXPECT_TRUE(contains(second.err, "another gdsmc run is writing 'out.h5' now (gdsmc process " +
                                         std::to_string(first.pid()) + " on host " + host_name() + ")"))
        << second.describe();
    // Another output beside it is not blocked.
    const ProcessResult other = run_gdsmc({"run", file.string(), "--quiet", "-o", "other.h5"}, dir.path());
    EXPECT_EQ(other.exit_code, 0) << other.describe();
    first.send(SIGINT);
    EXPECT_EQ(first.wait(30).exit_code, 130);
  }
  EXPECT_EQ(names(dir.path()), (std::vector<std::string>{"long.yaml", "other.h5", "pipeline.yaml"}))
      << "the lock is removed with the interrupted run";
  // A killed run's lock is stale: the next run takes it and removes it when it ends.
  {
    Process killed({"run", long_run.string(), "--quiet"}, dir.path());
    ASSERT_TRUE(killed.wait_until_catches(SIGINT));
    for (int k = 0; k < 3000 && temporaries(dir.path()).empty(); ++k)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    killed.send(SIGKILL);
    EXPECT_EQ(killed.wait(30).signal, SIGKILL);
  }
  EXPECT_TRUE(fs::exists(dir / ".out.h5.gdsmc-lock"));
  const ProcessResult after = run_gdsmc({"run", file.string(), "--quiet"}, dir.path());
  EXPECT_EQ(after.exit_code, 0) << after.describe();
  EXPECT_EQ(names(dir.path()), (std::vector<std::string>{"long.yaml", "other.h5", "out.h5", "pipeline.yaml"}));
}

}  // namespace
