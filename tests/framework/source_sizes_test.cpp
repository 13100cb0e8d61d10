// The house's rules for the host's framework/: no file over 600 lines and no function over 80, as
// scripts/check-source-sizes counts them; the stages include one another in one direction only, as
// scripts/check-layers reads their includes.
#include <gtest/gtest.h>

#include "test_support.hpp"

using namespace gdsmc::test;

namespace {
// A function of body_lines + 3 lines.
std::string function_of(int body_lines, const std::string& name) {
  std::string text = "int " + name + "(int x) {\n";
  for (int k = 0; k < body_lines; ++k) text += "  x += 1;  // a { in a comment\n";
  return text + "  return x;\n}\n";
}
// scripts/<script> run on `dir`.
ShellResult check(const fs::path& dir, const std::string& script = "check-source-sizes") {
  return shell("/usr/bin/python3 '" + (source_dir() / "scripts" / script).string() + "' '" + dir.string() + "'");
}
}  // namespace

TEST(SourceSizes, TheFrameworkKeepsItsFilesAndFunctionsWithinTheHouseSizes) {
  const ShellResult r = check(source_dir() / "framework");
  EXPECT_EQ(r.status, 0) << r.out;
}

// A function of 81 lines (its first to its last) is a breach, one of 80 is not; braces in strings,
// raw strings and comments do not count, and a class's member function is found.
TEST(SourceSizes, TheCheckFindsAFunctionOverEightyLinesAndAFileOverSixHundred) {
  TempDir dir;
  fs::create_directories(dir / "engine");
  dir.write("engine/sizes.cpp", "namespace a {\nconst char* kText = R\"(}{{)\";\nconst char c = '{';\n" +
                                    function_of(77, "eighty") + function_of(78, "eighty_one") +
                                    "struct S {\n  void member() const {\n" + std::string(81, '\n') + "  }\n};\n}\n");
  ShellResult r = check(dir.path());
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_TRUE(contains(r.out, "function eighty_one is 81 lines, more than 80")) << r.out;
  EXPECT_FALSE(contains(r.out, "function eighty ")) << r.out;
  EXPECT_TRUE(contains(r.out, "function member is 83 lines")) << r.out;
  EXPECT_FALSE(contains(r.out, "more than 600")) << r.out;
  dir.write("engine/long.cpp", std::string(601, '\n'));
  r = check(dir.path());
  EXPECT_TRUE(contains(r.out, "engine/long.cpp: 601 lines, more than 600")) << r.out;
}

TEST(StageArrows, TheFrameworksStagesIncludeOnlyEarlierStages) {
  EXPECT_EQ(check(source_dir() / "framework", "check-layers").status, 0)
      << check(source_dir() / "framework", "check-layers").out;
}

// config including engine (the arrow this check was written against) is a breach; engine including
// config and a stage including itself are not.
TEST(StageArrows, TheCheckFindsABackwardInclude) {
  TempDir dir;
  fs::create_directories(dir / "config");
  fs::create_directories(dir / "engine");
  dir.write("engine/step.cpp", "#include \"config/pipeline.hpp\"\n#include \"engine/step.hpp\"\n");
  ShellResult r = check(dir.path(), "check-layers");
  EXPECT_EQ(r.status, 0) << r.out;
  dir.write("config/run.cpp", "#include <cmath>\n\n#include \"engine/majorant.hpp\"\n");
  r = check(dir.path(), "check-layers");
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_TRUE(contains(r.out, "config/run.cpp:3: config includes engine, a later stage")) << r.out;
}
