// `gdsmc --help` lists every option of every command, each inside its command's section (a section
// starts with a line "gdsmc COMMAND"). The options are not listed here by hand: they come from the
// parsers' own tables, app/cli.cpp command_options() for run, validate and plugins, and the table
// of conformance/runner.cpp parse_config(), read from its source (it is local to that function).
// Every option found is also checked to be accepted by the executable and a made-up one to be
// refused, so that a broken extraction cannot pass silently.
//
// The help points to the documentation installed in <prefix>/share/doc/gdsmc: the last test
// installs this build and checks that the documents are there together, that every relative link
// between them resolves in the installed tree, and that there is an example project per plugin kind;
// and that every repository path an installed document names is installed or said to be in the
// source tree (unmarked_references()).
#include <unistd.h>

#include <cctype>
#include <regex>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "app/cli.hpp"
#include "test_support.hpp"

using namespace gdsmc::test;
using gdsmc::host::OptionSpec;

namespace {

// The text of `help` from the line "gdsmc COMMAND" up to the next line starting with "gdsmc ".
std::string section(const std::string& help, const std::string& command) {
  const std::string head = "\ngdsmc " + command;
  auto at = help.find(head + " ");
  if (at == std::string::npos) at = help.find(head + "\n");
  if (at == std::string::npos) return "";
  const auto end = help.find("\ngdsmc ", at + head.size());
  return help.substr(at, end == std::string::npos ? std::string::npos : end - at);
}

// `name` occurs in `text` as a whole option word (not as the prefix of a longer option).
bool lists(const std::string& text, const std::string& name) {
  auto word = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_'; };
  for (auto at = text.find(name); at != std::string::npos; at = text.find(name, at + 1)) {
    const bool left = at == 0 || !word(text[at - 1]);
    const bool right = at + name.size() >= text.size() || !word(text[at + name.size()]);
    if (left && right) return true;
  }
  return false;
}

// The option table of `gdsmc conformance`, from the source of its parser: every {{"--a", "-b"},
// "what"} entry of the OptionSpec table in parse_config().
std::vector<OptionSpec> conformance_options() {
  const std::string src = read_text(source_dir() / "framework/conformance/runner.cpp");
  std::vector<OptionSpec> specs;
  const auto fn = src.find("parse_config(");
  if (fn == std::string::npos) return specs;
  const auto table = src.find("std::vector<OptionSpec>", fn);
  if (table == std::string::npos) return specs;
  const auto end = src.find("};", table);
  const std::string body = src.substr(table, end - table);
  const std::regex entry(R"re(\{\{([^{}]*)\}\s*,\s*"([^"]*)"\s*\})re");
  const std::regex name(R"re("(-[^"]+)")re");
  for (std::sregex_iterator it(body.begin(), body.end(), entry), none; it != none; ++it) {
    OptionSpec s;
    const std::string names = (*it)[1];
    for (std::sregex_iterator n(names.begin(), names.end(), name); n != none; ++n) s.names.push_back((*n)[1]);
    s.needs = (*it)[2];
    if (!s.names.empty()) specs.push_back(s);
  }
  return specs;
}

struct Command {
  std::string name;
  std::vector<OptionSpec> options;
};

std::vector<Command> commands() {
  return {{"run", gdsmc::host::command_options("run")},
          {"validate", gdsmc::host::command_options("validate")},
          {"plugins", gdsmc::host::command_options("plugins")},
          {"conformance", conformance_options()},
          {"plot", gdsmc::host::command_options("plot")},
          {"inspect", gdsmc::host::command_options("inspect")},
          {"help", gdsmc::host::command_options("help")}};
}

// The command line that gives `command` option `name` (with a value if it takes one).
std::vector<std::string> with_option(const std::string& command, const OptionSpec& spec, const std::string& name) {
  std::vector<std::string> args{command, name};
  if (!spec.needs.empty()) args.push_back("1");
  return args;
}

// The installed documents name only what is installed. A document installed in
// <prefix>/share/doc/gdsmc that names a repository path (scripts/, configs/, tests/, framework/,
// plugins/, bench/, docs/, sdk/, cmake/; not after a '/', so build/plugins/..., lib/gdsmc/plugins/...
// and the HDF5 group /plugins/<role> are not such paths) must either name something the
// installation holds (at any depth: docs/X is share/doc/gdsmc/X, sdk/X is include/X or
// share/doc/gdsmc/X) or say that it is in the source tree, with one of two fixed phrases:
constexpr const char* kInSourceTree = "in the source tree";  // anywhere in the same paragraph
// or, for a document about work done in the repository (a validation report), once for every
// reference in the document, in its first paragraph after the title:
constexpr const char* kWholeDocumentInSourceTree = "every path named in this document is in the source tree";
// A paragraph ends at a blank line outside a code fence; each table row and each heading is a
// paragraph of its own; a list or a fenced block directly under a line of text is in its paragraph.
// The phrases are matched ignoring case and line breaks.

std::string folded(const std::string& text) {  // lower case, every run of white space one space
  std::string out;
  for (const char c : text) {
    if (std::isspace(static_cast<unsigned char>(c))) {
      if (!out.empty() && out.back() != ' ') out += ' ';
    } else {
      out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    }
  }
  return out;
}

// Whether `reference` names a path of the installation (`installed`: every file and directory,
// relative to the prefix): it, or what it becomes once installed, ends some installed path. A *
// stands for any name, <...> for one name; the text from a { on is left out (a brace list).
bool installed_path(std::string reference, const std::vector<std::string>& installed) {
  while (reference.rfind("../", 0) == 0) reference.erase(0, 3);
  for (const char* moved : {"docs/", "sdk/"})
    if (reference.rfind(moved, 0) == 0) reference.erase(0, std::string(moved).size());
  reference = reference.substr(0, reference.find('{'));
  while (!reference.empty() && reference.back() == '/') reference.pop_back();
  if (reference.empty()) return true;  // docs/ or sdk/ as a whole: installed
  std::string pattern;
  for (std::size_t i = 0; i < reference.size(); ++i) {
    const char c = reference[i];
    if (c == '*') {
      pattern += "[^/]*";
    } else if (c == '<' && reference.find('>', i) != std::string::npos) {
      pattern += "[^/]+";
      i = reference.find('>', i);
    } else {
      if (std::string("\\^$.|?+()[]{}").find(c) != std::string::npos) pattern += '\\';
      pattern += c;
    }
  }
  const std::regex path("(.*/)?" + pattern + "(/.*)?");
  return std::any_of(installed.begin(), installed.end(), [&](const std::string& p) { return std::regex_match(p, path); });
}

// "LINE: REFERENCE" for every repository path of `text` that is neither installed nor marked.
std::vector<std::string> unmarked_references(const std::string& text, const std::vector<std::string>& installed) {
  struct Paragraph {
    std::vector<std::pair<int, std::string>> lines;
    std::string text;
  };
  std::vector<Paragraph> paragraphs;
  {
    std::istringstream in(text);
    std::string line;
    bool fenced = false, open = false;
    for (int n = 1; std::getline(in, line); ++n) {
      const bool blank = line.find_first_not_of(" \t\r") == std::string::npos;
      const bool heading = !fenced && line.rfind("#", 0) == 0, row = !fenced && line.rfind("|", 0) == 0;
      if (!fenced && (blank || heading || row)) open = false;
      if (line.rfind("```", 0) == 0) fenced = !fenced;
      if (blank && !fenced) continue;
      if (!open) paragraphs.emplace_back();
      open = !heading && !row;
      paragraphs.back().lines.emplace_back(n, line);
      paragraphs.back().text += line + "\n";
    }
  }
  bool whole = false;  // the document-wide phrase in the first paragraph after the title
  for (const Paragraph& p : paragraphs)
    if (p.text.rfind("#", 0) != 0) {
      whole = folded(p.text).find(kWholeDocumentInSourceTree) != std::string::npos;
      break;
    }
  static const std::regex kReference(
      R"re((?:^|[^A-Za-z0-9_./<>-])((?:\.\./)*(?:scripts|configs|tests|framework|plugins|bench|docs|sdk|cmake)/[A-Za-z0-9_./*<>{}+-]*))re");
  std::vector<std::string> out;
  for (const Paragraph& p : paragraphs) {
    if (whole || folded(p.text).find(kInSourceTree) != std::string::npos) continue;
    for (const auto& [n, line] : p.lines)
      for (std::sregex_iterator it(line.begin(), line.end(), kReference), none; it != none; ++it) {
        std::string reference = (*it)[1];
        while (!reference.empty() && reference.back() == '.') reference.pop_back();
        if (!installed_path(reference, installed)) out.push_back(std::to_string(n) + ": " + reference);
      }
  }
  return out;
}

}  // namespace

TEST(CliHelp, TheTablesAreFound) {
  // Not empty: a failed extraction would make the listing test vacuous.
  for (const auto& c : commands()) {
    if (c.name == "help") {
      EXPECT_TRUE(c.options.empty()) << "gdsmc help takes no options";
      continue;
    }
    EXPECT_FALSE(c.options.empty()) << c.name;
  }
  EXPECT_GE(conformance_options().size(), 8u) << "the option table of conformance/runner.cpp parse_config() was not read";
}

TEST(CliHelp, MainHelpListsEveryOptionOfEveryCommand) {
  TempDir dir;
  const ProcessResult help = run_gdsmc({"--help"}, dir.path());
  ASSERT_EQ(help.exit_code, 0) << help.describe();
  EXPECT_EQ(run_gdsmc({"-h"}, dir.path()).out, help.out);
  EXPECT_EQ(run_gdsmc({"help"}, dir.path()).out, help.out);
  for (const auto& c : commands()) {
    const std::string text = section(help.out, c.name);
    ASSERT_FALSE(text.empty()) << "no section \"gdsmc " << c.name << "\" in gdsmc --help:\n" << help.out;
    for (const auto& spec : c.options)
      for (const auto& name : spec.names)
        EXPECT_TRUE(lists(text, name)) << "gdsmc --help does not list " << name << " under `gdsmc " << c.name
                                       << "`:\n" << text;
  }
  // The top-level options.
  for (const char* name : {"--help", "-h", "--version"}) EXPECT_TRUE(lists(help.out, name)) << name;
  // And where the documentation is installed.
  for (const char* doc : {"share/doc/gdsmc", "user-guide.md", "output-format.md", "plugin-author-guide.md"})
    EXPECT_NE(help.out.find(doc), std::string::npos) << doc;
}

TEST(CliHelp, EachCommandsHelpListsItsOptions) {
  TempDir dir;
  for (const auto& c : commands()) {
    if (c.name == "help") continue;
    const ProcessResult h = run_gdsmc({c.name, "--help"}, dir.path());
    ASSERT_EQ(h.exit_code, 0) << h.describe();
    EXPECT_EQ(run_gdsmc({"help", c.name}, dir.path()).out, h.out) << c.name;
    for (const auto& spec : c.options) {
      if (spec.names.front() == "--help") continue;  // the help itself
      for (const auto& name : spec.names)
        EXPECT_TRUE(lists(h.out, name)) << "gdsmc " << c.name << " --help does not list " << name << ":\n" << h.out;
    }
  }
}

// Every option taken from the tables is one the executable accepts, and the check can fail.
TEST(CliHelp, TheListedOptionsAreTheAcceptedOnes) {
  TempDir dir;
  for (const auto& c : commands()) {
    for (const auto& spec : c.options)
      for (const auto& name : spec.names) {
        const ProcessResult r = run_gdsmc(with_option(c.name, spec, name), dir.path());
        EXPECT_EQ(r.err.find("unknown option"), std::string::npos) << "gdsmc " << c.name << " " << name << ":\n"
                                                                    << r.describe();
        EXPECT_EQ(r.signal, 0) << r.describe();
      }
    if (c.name == "help") continue;
    const ProcessResult bad = run_gdsmc({c.name, "--no-such-option"}, dir.path());
    EXPECT_EQ(bad.exit_code, 2) << bad.describe();
    EXPECT_NE(bad.err.find("unknown option"), std::string::npos) << bad.describe();
  }
  // plugins takes only --plugin-path and --help: the options of run are refused there.
  for (const char* name : {"--set", "--output", "--quiet"}) {
    const ProcessResult r = run_gdsmc({"plugins", name, "x"}, dir.path());
    EXPECT_EQ(r.exit_code, 2) << r.describe();
    EXPECT_NE(r.err.find("plugins: unknown option"), std::string::npos) << r.describe();
  }
  const ProcessResult topic = run_gdsmc({"help", "no_such_command"}, dir.path());
  EXPECT_EQ(topic.exit_code, 2) << topic.describe();
}

TEST(InstalledDocumentation, IsWholeAndLinked) {
  TempDir dir;
  const fs::path prefix = dir.path() / "prefix";
  const ShellResult r = shell("cmake --install '" + std::string(GDSMC_BINARY_DIR) + "' --prefix '" + prefix.string() + "'");
  ASSERT_EQ(r.status, 0) << r.out;
  const fs::path doc = prefix / "share/doc/gdsmc";
  for (const char* name : {"user-guide.md", "output-format.md", "references.md", "plugin-author-guide.md"})
    EXPECT_TRUE(fs::is_regular_file(doc / name)) << name;
  // The plugin author guide links to the others by their installed names.
  const std::string guide = read_text(doc / "plugin-author-guide.md");
  for (const char* link : {"](user-guide.md)", "](output-format.md)", "](references.md)"})
    EXPECT_NE(guide.find(link), std::string::npos) << link;
  // Every relative link of every installed document resolves in the installed tree.
  const std::regex link(R"re(\]\(([^)#:\s]+)(#[^)]*)?\))re");
  for (const auto& e : fs::recursive_directory_iterator(doc)) {
    if (e.path().extension() != ".md" || e.path().string().find("/examples/") != std::string::npos) continue;
    const std::string text = read_text(e.path());
    for (std::sregex_iterator it(text.begin(), text.end(), link), none; it != none; ++it)
      EXPECT_TRUE(fs::exists(e.path().parent_path() / (*it)[1].str()))
          << e.path().lexically_relative(doc) << " links to " << (*it)[1] << ", which is not installed";
  }
  // One example project of each plugin kind, each a complete project (CMakeLists.txt with
  // find_package(gdsmc) and gdsmc_add_plugin, README.md, a pipeline).
  const std::map<std::string, std::string> examples = {{"viscoelastic_restitution", "collision rule"},
                                                       {"white_noise_heating", "forcing"},
                                                       {"cercignani_lampis_wall", "boundary"},
                                                       {"bimodal_maxwellian", "initial state"},
                                                       {"speed_distribution", "diagnostic"}};
  for (const auto& [name, kind] : examples) {
    const fs::path project = doc / "examples" / name;
    const std::string cmake = read_text(project / "CMakeLists.txt");
    EXPECT_NE(cmake.find("find_package(gdsmc CONFIG REQUIRED)"), std::string::npos) << kind << ": " << name;
    EXPECT_NE(cmake.find("gdsmc_add_plugin(" + name), std::string::npos) << kind << ": " << name;
    EXPECT_TRUE(fs::is_regular_file(project / "README.md")) << kind << ": " << name;
    EXPECT_TRUE(fs::is_regular_file(project / (name + ".cpp"))) << kind << ": " << name;
    bool yaml = false;
    for (const auto& f : fs::directory_iterator(project)) yaml = yaml || f.path().extension() == ".yaml";
    EXPECT_TRUE(yaml) << kind << ": " << name << " has no pipeline";
  }
}

// The installed documents name only what is installed, or say that a path is in the source tree
// (the phrases and the rule: unmarked_references()). The checker is tried first on made-up text, so
// that a rule that finds nothing cannot pass.
TEST(InstalledDocumentation, NamesOnlyWhatIsInstalledOrSaysItIsInTheSourceTree) {
  const std::vector<std::string> some = {"share", "share/gdsmc", "share/gdsmc/gdsmc_plot.py", "share/doc/gdsmc/validation",
                                         "share/doc/gdsmc/validation/usf.md", "include/gdsmc/version.hpp"};
  EXPECT_EQ(unmarked_references("# T\n\nRun `scripts/validate-usf` and `configs/hcs.yaml`.\n", some),
            (std::vector<std::string>{"3: scripts/validate-usf", "3: configs/hcs.yaml"}));
  EXPECT_EQ(unmarked_references("Text.\n\nIn the source\ntree: `scripts/validate-usf`.\n\n| a | tests/x_test.cpp |\n", some),
            std::vector<std::string>{"6: tests/x_test.cpp"});
  EXPECT_EQ(unmarked_references("Text, then a block:\n```\ngdsmc run configs/hcs.yaml  # in the source tree\n\n- x\n```\n", some),
            std::vector<std::string>{});
  EXPECT_EQ(unmarked_references("# T\n\nEvery path named in this document is in the source tree.\n\n`scripts/a`\n", some),
            std::vector<std::string>{});
  EXPECT_EQ(unmarked_references("`docs/validation/usf.md`, `sdk/include/gdsmc/version.hpp`, build/plugins/x.so, "
                                "/plugins/<role>, `scripts/gdsmc_plot.py`\n",
                                some),
            std::vector<std::string>{"1: scripts/gdsmc_plot.py"});

  TempDir dir;
  const fs::path prefix = dir.path() / "prefix";
  const ShellResult r = shell("cmake --install '" + std::string(GDSMC_BINARY_DIR) + "' --prefix '" + prefix.string() + "'");
  ASSERT_EQ(r.status, 0) << r.out;
  std::vector<std::string> installed;
  for (const auto& e : fs::recursive_directory_iterator(prefix)) installed.push_back(e.path().lexically_relative(prefix).string());
  const fs::path doc = prefix / "share/doc/gdsmc";
  std::size_t documents = 0;
  for (const auto& e : fs::recursive_directory_iterator(doc)) {
    if (!e.is_regular_file() || e.path().extension() == ".png") continue;
    ++documents;
    for (const std::string& bad : unmarked_references(read_text(e.path()), installed))
      ADD_FAILURE() << "share/doc/gdsmc/" << e.path().lexically_relative(doc).string() << ":" << bad
                    << ", which the installation does not hold: name the installed path, or say that it is \""
                    << kInSourceTree << "\" in its paragraph";
  }
  EXPECT_GE(documents, 15u);  // the documents, the validation reports and the examples' files
}
