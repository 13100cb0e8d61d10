// The plugin search path: a broken library anywhere on it costs a warning naming it and why, never
// the process, and a missing directory or a shadowed plugin is never silent.
#include <gtest/gtest.h>

#include <dlfcn.h>

#include <chrono>
#include <csignal>
#include <thread>

#include "plugins/child_process.hpp"
#include "test_support.hpp"
#include "util/text.hpp"

namespace {

using namespace gdsmc::test;
using gdsmc::host::ChildOutcome;
using gdsmc::host::ChildReport;
using gdsmc::host::PluginRegistry;

// The first `bytes` bytes of `from`, written to `to`.
void copy_prefix(const fs::path& from, const fs::path& to, std::size_t bytes) {
  const std::string all = read_text(from);
  std::ofstream(to, std::ios::binary) << all.substr(0, std::min(bytes, all.size()));
}

fs::path real_plugin() { return plugin_dir() / "gdsmc_temperature.so"; }

// A plugin directory with one library of each kind that used to crash or confuse the host, and
// for each file a phrase its warning must contain.
struct BrokenPluginDir {
  TempDir dir;
  std::map<fs::path, std::string> reasons;
  BrokenPluginDir() {
    fs::copy_file(test_plugin("aborting_constructor"), dir / "aborts.so");
    reasons[dir / "aborts.so"] = gdsmc::host::fmt("crashed while being loaded (signal %d", SIGABRT);
    fs::copy_file(test_plugin("null_entry"), dir / "null_entry.so");
    reasons[dir / "null_entry.so"] = gdsmc::host::fmt("crashed while being loaded (signal %d", SIGSEGV);
    copy_prefix(real_plugin(), dir / "truncated.so", fs::file_size(real_plugin()) / 2);  // dlopen: SIGBUS
    reasons[dir / "truncated.so"] = "is truncated";
    dir.write("x.so", "");
    reasons[dir / "x.so"] = "is empty";
    fs::create_directory(dir / "y.so");
    reasons[dir / "y.so"] = "is a directory";
    fs::create_symlink("z.so", dir / "z.so");
    reasons[dir / "z.so"] = "symbolic link loop";
  }
  // Each file has exactly one warning, naming it and why, and there are no others.
  void expect_one_warning_each(const std::string& err, const std::string& what) const {
    const auto warnings = lines_starting(err, "warning: ");
    for (const auto& [file, reason] : reasons) {
      const auto mine = lines_starting(err, "warning: " + file.string() + ": ");
      ASSERT_EQ(mine.size(), 1u) << what << ": " << file << "\n" << err;
      EXPECT_TRUE(contains(mine[0], reason)) << what << ": " << mine[0];
    }
    EXPECT_EQ(warnings.size(), reasons.size()) << what << "\n" << err;
  }
};

// plugins, validate and a short run all succeed with every kind of broken library on the plugin
// path, each reported once as a warning (the old host died of SIGABRT, SIGSEGV or SIGBUS, stopped
// at the link loop, and passed over the directory without a word).
TEST(PluginPath, BrokenLibrariesOnThePathAreWarningsForEveryCommand) {
  BrokenPluginDir broken;
  TempDir work;
  const std::string hcs = (source_dir() / "configs" / "hcs.yaml").string();
  const std::string path = broken.dir.path().string();

  const ProcessResult list = run_gdsmc({"plugins", "--plugin-path", path}, work.path(), 60);
  ASSERT_EQ(list.exit_code, 0) << list.describe();
  EXPECT_TRUE(contains(list.out, "maxwellian")) << list.describe();
  broken.expect_one_warning_each(list.err, "plugins");

  const ProcessResult validate =
      run_gdsmc({"validate", hcs, "--set", "run.particles=1000", "--plugin-path", path}, work.path(), 60);
  ASSERT_EQ(validate.exit_code, 0) << validate.describe();
  EXPECT_TRUE(contains(validate.out, "valid")) << validate.describe();
  broken.expect_one_warning_each(validate.err, "validate");

  const ProcessResult run = run_gdsmc({"run", hcs, "--set", "run.particles=1000", "--set",
                                       "run.stop.collisions_per_particle=1", "--set", "run.average_after.collisions_per_particle=0", "-q", "-o", "out.h5", "--plugin-path", path},
                                      work.path(), 60);
  ASSERT_EQ(run.exit_code, 0) << run.describe();
  EXPECT_TRUE(fs::is_regular_file(work / "out.h5"));
  broken.expect_one_warning_each(run.err, "run");
}

// The same in this process: the registry examines each library without loading it here, so the
// test process survives the libraries that abort or crash when loaded.
TEST(PluginPath, RegistrySurvivesBrokenLibraries) {
  BrokenPluginDir broken;
  PluginRegistry reg;
  reg.add(broken.dir.path());
  EXPECT_TRUE(reg.available().empty());
  EXPECT_TRUE(reg.plugins().empty());
  broken.expect_one_warning_each("warning: " + join(reg.warnings(), "\nwarning: ") + "\n", "registry");
}

// Named explicitly (a .so argument of `gdsmc plugins`), each broken file is an error that names it
// and says why: exit 1, not a signal.
TEST(PluginPath, BrokenLibraryNamedExplicitlyIsAnError) {
  BrokenPluginDir broken;
  TempDir work;
  for (const auto& [file, reason] : broken.reasons) {
    const ProcessResult r = run_gdsmc({"plugins", file.string()}, work.path(), 60);
    EXPECT_EQ(r.exit_code, 1) << r.describe();
    EXPECT_EQ(r.signal, 0) << r.describe();
    EXPECT_TRUE(contains(r.err, "error: " + file.string() + ": ")) << r.describe();
    EXPECT_TRUE(contains(r.err, reason)) << r.describe();
  }
}

// The checks of the file itself, before anything is loaded: a real plugin passes; a copy cut
// anywhere (inside the ELF header, the program headers, a loaded segment, or only the section
// header table at the end) is truncated; a text file is not a shared library; a dangling link
// does not exist.
TEST(PluginPath, LibraryFileChecks) {
  using gdsmc::host::library_file_problem;
  TempDir dir;
  EXPECT_EQ(library_file_problem(real_plugin()), "");
  const auto size = fs::file_size(real_plugin());
  for (std::size_t bytes : {std::size_t{20}, std::size_t{100}, std::size_t{1000}, size / 2, size - 1}) {
    const fs::path cut = dir / ("cut" + std::to_string(bytes) + ".so");
    copy_prefix(real_plugin(), cut, bytes);
    EXPECT_TRUE(contains(library_file_problem(cut), "truncated")) << bytes << ": " << library_file_problem(cut);
  }
  const fs::path text = dir.write("text.so", "#!/bin/sh\necho this is not a library, but it is long enough to hold an ELF header\n");
  EXPECT_TRUE(contains(library_file_problem(text), "not a shared library")) << library_file_problem(text);
  fs::create_symlink("nowhere.so", dir / "dangling.so");
  EXPECT_TRUE(contains(library_file_problem(dir / "dangling.so"), "does not exist"))
      << library_file_problem(dir / "dangling.so");
}

// Whether the shared library `file` is mapped in this process (RTLD_NOLOAD never loads).
bool is_loaded(const fs::path& file) {
  void* h = ::dlopen(file.c_str(), RTLD_NOW | RTLD_NOLOAD);
  if (!h) return false;
  ::dlclose(h);
  return true;
}

// Listing a plugin directory loads none of its libraries into this process; a plugin is loaded
// when it is first used, and only that one.
TEST(PluginPath, OnlyPluginsInUseAreLoadedInProcess) {
  TempDir dir;  // copies, so that no other test of this process has loaded these very files
  const fs::path temperature = dir / "gdsmc_temperature.so", maxwellian = dir / "gdsmc_maxwellian.so";
  fs::copy_file(real_plugin(), temperature);
  fs::copy_file(plugin_dir() / "gdsmc_maxwellian.so", maxwellian);
  PluginRegistry reg;
  reg.add(dir.path());
  ASSERT_EQ(reg.available().size(), 2u) << join(reg.warnings(), "\n");
  EXPECT_EQ(reg.names_of_kind(gdsmc::PluginKind::diagnostic), std::vector<std::string>{"temperature"});
  EXPECT_FALSE(is_loaded(temperature));
  EXPECT_FALSE(is_loaded(maxwellian));
  const auto* lp = reg.find("maxwellian");
  ASSERT_NE(lp, nullptr);
  EXPECT_EQ(lp->descriptor->name, "maxwellian");
  EXPECT_TRUE(is_loaded(maxwellian));
  EXPECT_FALSE(is_loaded(temperature));
}

// The child process the probe runs in: what was sent before a crash is kept, the signal is
// reported, an exit from plugin code is not taken for a finished child, and a hang is killed after
// the time limit (measured without any message, so a slow but progressing child is not killed).
TEST(PluginPath, ChildProcessReportsCrashesExitsAndHangs) {
  using gdsmc::host::run_in_child;
  const ChildOutcome ok = run_in_child([](ChildReport& r) { r.send("a"); r.send(std::string("b\0c", 3)); }, 10, true);
  EXPECT_TRUE(ok.finished);
  EXPECT_EQ(ok.messages, (std::vector<std::string>{"a", std::string("b\0c", 3)}));

  const ChildOutcome crash = run_in_child([](ChildReport& r) { r.send("before"); std::raise(SIGSEGV); }, 10, true);
  EXPECT_FALSE(crash.finished);
  EXPECT_EQ(crash.signal, SIGSEGV);
  EXPECT_FALSE(crash.timed_out);
  EXPECT_EQ(crash.messages, std::vector<std::string>{"before"});

  const ChildOutcome exited = run_in_child([](ChildReport&) { std::exit(0); }, 10, true);
  EXPECT_FALSE(exited.finished);
  EXPECT_EQ(exited.signal, 0);

  const auto start = std::chrono::steady_clock::now();
  const ChildOutcome hang = run_in_child(
      [](ChildReport& r) {
        for (int k = 0; k < 4; ++k) {  // 4 x 0.1 s with a message each: within a 0.3 s limit
          std::this_thread::sleep_for(std::chrono::milliseconds(100));
          r.send("tick");
        }
        std::this_thread::sleep_for(std::chrono::seconds(60));
      },
      0.3, true);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_TRUE(hang.timed_out);
  EXPECT_FALSE(hang.finished);
  EXPECT_EQ(hang.messages.size(), 4u);
  EXPECT_LT(seconds, 10.0);
}

// validate and run warn about a `plugins:` entry or --plugin-path that does not exist and
// about a plugin shadowed by another of the same name, and the output records which library ran.
TEST(PluginPath, MissingDirectoriesAndShadowedPluginsAreWarnedAbout) {
  TempDir dir;
  fs::create_directory(dir / "shadow");
  const fs::path copy = dir / "shadow" / "gdsmc_temperature.so";
  fs::copy_file(real_plugin(), copy);
  const std::string yaml = read_text(source_dir() / "configs" / "hcs.yaml") + "plugins: [missing, shadow]\n";
  const fs::path file = dir.write("pipeline.yaml", yaml);
  const std::string missing = (dir / "missing").string(), elsewhere = (dir / "elsewhere").string();
  auto expect_warnings = [&](const ProcessResult& r, const std::string& what) {
    EXPECT_EQ(r.exit_code, 0) << what << "\n" << r.describe();
    const auto w = lines_starting(r.err, "warning: ");
    ASSERT_EQ(w.size(), 3u) << what << "\n" << r.describe();
    EXPECT_TRUE(contains(r.err, "warning: " + file.string() + ":" + std::to_string(line_of(yaml, "plugins: [missing")) +
                                    ":"))
        << r.describe();
    EXPECT_TRUE(contains(r.err, "plugins[0]: " + missing + " does not exist")) << r.describe();
    EXPECT_TRUE(contains(r.err, "warning: " + elsewhere + ": plugin search path entry does not exist")) << r.describe();
    EXPECT_TRUE(contains(r.err, real_plugin().string() + ": plugin 'temperature' is shadowed by " + copy.string()))
        << r.describe();
  };
  expect_warnings(run_gdsmc({"validate", file.string(), "--set", "run.particles=1000", "--plugin-path", elsewhere},
                            dir.path(), 60),
                  "validate");
  expect_warnings(run_gdsmc({"run", file.string(), "--set", "run.particles=1000", "--set",
                             "run.stop.collisions_per_particle=1", "--set", "run.average_after.collisions_per_particle=0", "-q", "-o", "out.h5", "--plugin-path", elsewhere},
                            dir.path(), 60),
                  "run");
  // The provenance names the library that was used: the shadowing copy.
  h5::File out(dir / "out.h5");
  bool found = false;
  for (const auto& role : h5::members(out.id(), "/plugins")) {
    if (h5::read_string_attribute(out.id(), "/plugins/" + role, "plugin") != "temperature") continue;
    found = true;
    EXPECT_EQ(h5::read_string_attribute(out.id(), "/plugins/" + role, "library"), copy.string());
  }
  EXPECT_TRUE(found);
}

}  // namespace
