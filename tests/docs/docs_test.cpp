// The documentation tested against the program: every YAML snippet and every gdsmc
// command line of README.md and docs/ goes through `gdsmc validate` (or the command's --help), the
// h5py recipes run on the files the commands of their document write, and the dataset names a
// plugin's documentation gives are those its output holds.
//
// What each kind of snippet becomes:
// - a ```yaml block: a whole pipeline (it has run, system, initial_state and collision) is
//   validated as it is; a part of one is merged key by key into a small homogeneous pipeline
//   (kSmallHcsPipeline) and validated. A plugin the document builds itself (gdsmc_add_plugin(NAME ...), the
//   tutorial's my_rule) may be unknown: nothing else may be wrong.
// - a command line (in a code block, an indented block or `inline code`): a synopsis (with
//   placeholders such as PIPELINE.yaml, NAME, [..]) must name only options its command's help
//   lists; a concrete `gdsmc run` is checked by `gdsmc validate` with the same arguments (without
//   --resume: there is no checkpoint) or, in a document with h5py recipes, run for real in a small
//   version that the document itself gives; validate, plugins, help and --version run as they are;
//   conformance runs with --list; inspect and plot run on a file a run of the document wrote, else
//   their options are checked against their help. A file argument the document only pretends to
//   have (its own tutorial plugin) turns the command into that option check.
// - a ```python block: run with /usr/bin/python3 in the directory where the document's runs wrote
//   their files (python3-h5py and python3-numpy, installed by scripts/install-deps).
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <regex>
#include <set>

#include "test_support.hpp"

using namespace gdsmc::test;
using namespace gdsmc::test::h5;

namespace {

// The documents: README.md and every docs/**/*.md.
std::vector<fs::path> documents() {
  std::vector<fs::path> docs{source_dir() / "README.md"};
  for (const auto& e : fs::recursive_directory_iterator(source_dir() / "docs"))
    if (e.is_regular_file() && e.path().extension() == ".md") docs.push_back(e.path());
  std::sort(docs.begin(), docs.end());
  return docs;
}

struct Block {
  std::string lang;  // after the fence; "indented" for a 4-space block
  int line = 0;      // first line of the text (1-based)
  std::string text;
};

struct Document {
  fs::path file;
  std::string text;
  std::vector<Block> blocks;
  std::string prose;  // the text outside code blocks
  std::string where(int line) const { return fs::relative(file, source_dir()).string() + ":" + std::to_string(line); }
};

Document read_document(const fs::path& file) {
  Document d{file, read_text(file), {}, {}};
  std::istringstream in(d.text);
  std::string line, previous;
  bool fenced = false, indented = false;
  Block block;
  for (int n = 1; std::getline(in, line); ++n) {
    const bool blank = line.find_first_not_of(' ') == std::string::npos;
    if (indented && !blank && line.rfind("    ", 0) != 0) {
      d.blocks.push_back(block);
      indented = false;
    }
    if (!fenced && line.rfind("```", 0) == 0) {
      block = Block{line.substr(3), n + 1, ""};
      fenced = true;
    } else if (fenced && line.rfind("```", 0) == 0) {
      d.blocks.push_back(block);
      fenced = false;
    } else if (fenced) {
      block.text += line + "\n";
    } else if (indented) {
      block.text += (blank ? "" : line.substr(4)) + "\n";
    } else if (!blank && line.rfind("    ", 0) == 0 && previous.find_first_not_of(' ') == std::string::npos) {
      block = Block{"indented", n, line.substr(4) + "\n"};
      indented = true;
    } else {
      d.prose += line + "\n";
    }
    previous = line;
  }
  if (indented) d.blocks.push_back(block);
  return d;
}

// A command line: the text after the word that names the executable.
struct Command {
  int line = 0;
  std::string args;  // as written (shell quoting)
};

// `line` without a trailing shell comment (a # after a space, outside quotes).
std::string without_comment(const std::string& line) {
  char quote = 0;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '\'' || c == '"') {
      quote = c;
    } else if (c == '#' && (i == 0 || line[i - 1] == ' ')) {
      return line.substr(0, i);
    }
  }
  return line;
}

// The gdsmc command in `text` (one logical line), or nothing: it starts with gdsmc, a path ending
// in /gdsmc, optionally after "$ ".
std::optional<std::string> gdsmc_args(std::string text) {
  static const std::regex kStart(R"(^\s*(\$\s+)?(\S*/)?gdsmc(\s+|$))");
  std::smatch m;
  if (!std::regex_search(text, m, kStart)) return std::nullopt;
  return std::string(m.suffix());
}

std::vector<Command> commands(const Document& d) {
  std::vector<Command> out;
  for (const auto& b : d.blocks) {
    if (b.lang != "" && b.lang != "sh" && b.lang != "bash" && b.lang != "text" && b.lang != "indented") continue;
    std::istringstream in(b.text);
    std::string line, logical;
    int first = 0;
    for (int n = b.line; std::getline(in, line); ++n) {
      if (logical.empty()) first = n;
      line = without_comment(line);
      const bool continued = !line.empty() && line.find_last_not_of(' ') != std::string::npos &&
                             line[line.find_last_not_of(' ')] == '\\';
      logical += continued ? line.substr(0, line.find_last_not_of(' ')) + " " : line;
      if (continued) continue;
      if (auto args = gdsmc_args(logical)) out.push_back({first, *args});
      logical.clear();
    }
  }
  // `inline code` in the prose (it may wrap across lines).
  static const std::regex kInline("`([^`]+)`");
  for (auto it = std::sregex_iterator(d.prose.begin(), d.prose.end(), kInline); it != std::sregex_iterator(); ++it) {
    const std::string written = (*it)[1];
    std::string code = written;
    std::replace(code.begin(), code.end(), '\n', ' ');
    if (auto args = gdsmc_args(code)) out.push_back({line_of(d.text, "`" + written.substr(0, written.find('\n'))), *args});
  }
  return out;
}

// Words of a shell command line (quotes removed; enough for the options and file names here).
std::vector<std::string> words(const std::string& args) {
  std::vector<std::string> w;
  std::string cur;
  char quote = 0;
  bool any = false;
  for (char c : args) {
    if (quote) {
      if (c == quote) quote = 0;
      else cur += c;
    } else if (c == '\'' || c == '"') {
      quote = c;
      any = true;
    } else if (c == ' ' || c == '\t') {
      if (!cur.empty() || any) w.push_back(cur);
      cur.clear();
      any = false;
    } else {
      cur += c;
    }
  }
  if (!cur.empty() || any) w.push_back(cur);
  return w;
}

// A synopsis rather than a command: placeholders in capitals (PIPELINE.yaml, NAME, FILE.so),
// optional parts in brackets, alternatives, ellipses.
bool is_synopsis(const std::vector<std::string>& w) {
  static const std::regex kPlaceholder(R"((^|[^A-Za-z0-9_])[A-Z][A-Z_]*[A-Z]?(\.[a-z0-9]+)?([^A-Za-z0-9_]|$))");
  for (std::size_t k = 0; k < w.size(); ++k) {
    const std::string& word = w[k];
    if (word == "key.path=value" || word == "key.path") return true;
    if (k > 0 && w[k - 1] == "--set") continue;  // a YAML value: brackets and capitals are its own
    if (word.find('[') != std::string::npos || word.find('|') != std::string::npos || word.find("...") != std::string::npos ||
        word.find("\xE2\x80\xA6") != std::string::npos)
      return true;
    if (std::regex_search(word, kPlaceholder)) return true;
  }
  return false;
}

const std::set<std::string> kCommands = {"run", "validate", "plugins", "conformance", "plot", "inspect", "help"};

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// `gdsmc COMMAND --help`, or the top-level help.
std::string help_of(const std::string& command, const fs::path& cwd) {
  const ProcessResult r = command.empty() || command == "help" || command[0] == '-' ? run_gdsmc({"--help"}, cwd)
                                                                                   : run_gdsmc({command, "--help"}, cwd);
  EXPECT_EQ(r.exit_code, 0) << command << ": " << r.describe();
  return r.out;
}

// Every option of `w` appears in the help of its command.
void expect_options_in_help(const std::string& where, const std::vector<std::string>& w, const fs::path& cwd) {
  const std::string command = w.empty() ? "" : w[0];
  if (!command.empty() && command[0] != '-') {
    EXPECT_TRUE(kCommands.count(command)) << where << ": unknown command '" << command << "'";
    if (!kCommands.count(command)) return;
  }
  const std::string help = help_of(command, cwd);
  for (std::string word : w) {
    word.erase(std::remove(word.begin(), word.end(), '['), word.end());
    word.erase(std::remove(word.begin(), word.end(), ']'), word.end());
    if (word.size() < 2 || word[0] != '-' || word == "-" || word == "--") continue;
    const std::string option = word.substr(0, word.find('='));
    static const std::regex kDigits("^-[0-9.]");
    if (std::regex_search(option, kDigits)) continue;  // a negative number
    EXPECT_TRUE(contains(help, option + " ") || contains(help, option + ",") || contains(help, option + "\n"))
        << where << ": option " << option << " is not in the help of `gdsmc " << command << "`";
  }
}

// The directory the commands of one document run in: configs/, scripts/ and build/ of this tree
// are reachable under their usual names.
struct Workdir {
  TempDir dir;
  Workdir() {
    fs::create_directory_symlink(source_dir() / "configs", dir / "configs");
    fs::create_directory_symlink(source_dir() / "scripts", dir / "scripts");
    fs::create_directory_symlink(GDSMC_BINARY_DIR, dir / "build");
  }
};

// The run of a shell command line in `cwd`, gdsmc being this build's executable.
ShellResult gdsmc_shell(const fs::path& cwd, const std::string& args) {
  return shell("cd " + shell_quote(cwd.string()) + " && " + shell_quote(executable().string()) + " " + args);
}

// A file argument that does not exist here: the pipeline of a `run`, a .so, a .h5.
bool names_missing_file(const std::vector<std::string>& w, const fs::path& cwd) {
  for (std::size_t k = 1; k < w.size(); ++k) {
    const std::string& a = w[k];
    if (a.empty() || a[0] == '-' || (k > 0 && (w[k - 1] == "-o" || w[k - 1] == "--output" || w[k - 1] == "--set" ||
                                               w[k - 1] == "--out")))
      continue;
    for (const char* ext : {".yaml", ".so", ".h5"})
      if (a.size() > std::strlen(ext) && a.compare(a.size() - std::strlen(ext), std::strlen(ext), ext) == 0 &&
          !fs::exists(cwd / a))
        return true;
  }
  return false;
}

// `args` with the pipeline argument of run/validate found under configs/ when it is not here
// (the user guide's `gdsmc run poiseuille.yaml --resume`).
std::string with_config_path(const std::string& args, const std::vector<std::string>& w, const fs::path& cwd) {
  if (w.size() < 2 || (w[0] != "run" && w[0] != "validate") || fs::exists(cwd / w[1]) ||
      !fs::exists(cwd / "configs" / w[1]))
    return args;
  const auto at = args.find(w[1]);
  return args.substr(0, at) + "configs/" + args.substr(at);
}

// The plugins a document builds itself (gdsmc_add_plugin(NAME ...)).
std::set<std::string> own_plugins(const Document& d) {
  std::set<std::string> names;
  static const std::regex kAdd(R"(gdsmc_add_plugin\((\w+))");
  for (auto it = std::sregex_iterator(d.text.begin(), d.text.end(), kAdd); it != std::sregex_iterator(); ++it)
    names.insert((*it)[1]);
  return names;
}

// A command line of `d`, checked in `cwd` (`execute`: `gdsmc run` runs for real).
void check_command(const Document& d, const Command& c, const fs::path& cwd, bool execute) {
  const std::string where = d.where(c.line) + ": gdsmc " + c.args;
  SCOPED_TRACE(where);
  const std::vector<std::string> w = words(c.args);
  if (w.empty() || is_synopsis(w)) return expect_options_in_help(where, w, cwd);
  const std::string& command = w[0];
  if (command != "--help" && command != "-h" && command != "--version" && !kCommands.count(command)) {
    ADD_FAILURE() << where << ": unknown command '" << command << "'";
    return;
  }
  // The command named in prose (`gdsmc validate`) rather than a command line.
  static const std::set<std::string> kNeedArguments = {"run", "validate", "conformance", "plot", "inspect"};
  const bool positional = std::any_of(w.begin() + 1, w.end(), [](const std::string& a) { return !a.empty() && a[0] != '-'; });
  if (!positional && kNeedArguments.count(command)) return expect_options_in_help(where, w, cwd);
  // The document's own tutorial plugin is not installed here.
  for (const auto& name : own_plugins(d))
    if (std::find(w.begin(), w.end(), name) != w.end() || contains(c.args, "gdsmc_" + name + ".so"))
      return expect_options_in_help(where, w, cwd);
  std::string args = with_config_path(c.args, w, cwd);
  if (names_missing_file(words(args), cwd) && !(command == "run" && execute))
    return expect_options_in_help(where, w, cwd);
  if (command == "plot") return expect_options_in_help(where, w, cwd);  // drawing is plot_inspect_test's
  if (command == "run" && !execute) args = "validate" + args.substr(3);
  if (command == "run" || command == "validate") args = std::regex_replace(args, std::regex(R"(\s--resume\b)"), "");
  if (command == "conformance") args += " --list";
  if (command == "run") args += " --quiet";
  const ShellResult r = gdsmc_shell(cwd, args);
  EXPECT_EQ(r.status, 0) << where << "\nran: gdsmc " << args << "\n" << r.out;
}

void merge(YAML::Node base, const YAML::Node& part) {
  for (auto it = part.begin(); it != part.end(); ++it) {
    const std::string key = it->first.Scalar();
    if (it->second.IsMap() && base[key] && base[key].IsMap()) merge(base[key], it->second);
    else base[key] = it->second;
  }
}

void check_yaml(const Document& d, const Block& b, const fs::path& cwd) {
  const std::string where = d.where(b.line) + " (```yaml)";
  SCOPED_TRACE(where);
  YAML::Node part;
  try {
    part = YAML::Load(b.text);
  } catch (const YAML::Exception& e) {
    ADD_FAILURE() << where << ": not YAML: " << e.what();
    return;
  }
  ASSERT_TRUE(part.IsMap()) << where;
  std::string text = b.text;
  if (!(part["run"] && part["system"] && part["initial_state"] && part["collision"])) {
    YAML::Node base = YAML::Load(kSmallHcsPipeline);
    merge(base, part);
    YAML::Emitter e;
    e << base;
    text = e.c_str();
  }
  const fs::path file = cwd / ("snippet-" + std::to_string(b.line) + ".yaml");
  std::ofstream(file) << text;
  const ShellResult r = gdsmc_shell(cwd, "validate " + shell_quote(file.string()));
  if (r.status == 0) return;
  // Only unknown plugins the document builds itself may be wrong.
  std::istringstream lines(r.out);
  bool other = false;
  const auto own = own_plugins(d);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("error: ", 0) != 0) continue;
    bool excused = false;
    for (const auto& name : own) excused = excused || contains(line, "plugin '" + name + "'");
    other = other || !excused;
  }
  EXPECT_FALSE(other) << where << ": `gdsmc validate` refuses it:\n" << r.out << "\n--- as validated ---\n" << text;
}

void check_python(const Document& d, const Block& b, const fs::path& cwd) {
  const std::string where = d.where(b.line) + " (```python)";
  const fs::path file = cwd / ("recipe-" + std::to_string(b.line) + ".py");
  std::ofstream(file) << b.text;
  const ShellResult r = shell("cd " + shell_quote(cwd.string()) + " && MPLBACKEND=Agg /usr/bin/python3 " +
                              shell_quote(file.string()));
  EXPECT_EQ(r.status, 0) << where << ": the recipe fails on the files the document's commands wrote:\n" << r.out;
}

// The names of the datasets (and histogram groups) a diagnostic wrote, without what the host adds
// to every group (time, s, bin centres, each realization's copy, standard errors over realizations,
// steady averages, the seed checks of errors) and with the plugin's own error and mean companions reduced to their quantity:
// R0_mean, R0_standard_error -> R0; steady_T_error -> steady_T.
std::set<std::string> plugin_datasets(hid_t file, const std::string& group) {
  static const std::set<std::string> kHost = {"time", "collisions_per_particle", "bin_centre", "realizations"};
  static const std::regex kCompanion(R"((\.steady_mean|\.steady_stderr|_stderr)?(_seed_chi2_dof|_seed_chi2_dof_weighted)?$)");
  static const std::regex kOwn(R"((_standard_error|_error|_mean)$)");
  std::set<std::string> names;
  for (std::string n : members(file, group)) {
    n = std::regex_replace(n, kCompanion, "");
    n = std::regex_replace(n, kOwn, "");
    if (!kHost.count(n)) names.insert(n);
  }
  return names;
}

// `doc` names the dataset `name`: as a word, or by a family with a placeholder
// (added_by_<stage> names added_by_collisions).
bool documents_name(const std::string& doc, const std::string& name) {
  static const std::regex kSpecial(R"([.^$|()\[\]{}*+?\\])");
  const std::regex word("(^|[^A-Za-z0-9_])" + std::regex_replace(name, kSpecial, "\\$&") + "([^A-Za-z0-9_]|$)");
  if (std::regex_search(doc, word)) return true;
  // A family: a name with placeholders, e.g. <series>.steady_mean, <w>_momentum_flux_<a>, T[<name>].
  static const std::regex kFamily(R"([A-Za-z0-9_.\[\]]*(<[a-z_]+>[A-Za-z0-9_.\[\]]*)+)");
  for (auto it = std::sregex_iterator(doc.begin(), doc.end(), kFamily); it != std::sregex_iterator(); ++it) {
    const std::string family = std::regex_replace(it->str(), kSpecial, "\\$&");
    const std::string pattern = std::regex_replace(family, std::regex("<[a-z_]+>"), "[A-Za-z0-9_.]+");
    if (std::regex_match(name, std::regex(pattern))) return true;
  }
  return false;
}

// Every dataset each diagnostic of `file` wrote is named, as a word, in `gdsmc plugins PLUGIN`.
void expect_datasets_documented(const fs::path& file, std::map<std::string, std::string>& docs) {
  SCOPED_TRACE(file.filename().string());
  const File f(file);
  std::vector<std::string> roots{"/"};
  if (exists(f.id(), "/cases"))
    for (const auto& k : members(f.id(), "/cases")) roots.push_back("/cases/" + k + "/");
  for (const auto& root : roots) {
    if (!exists(f.id(), root + "plugins")) continue;
    for (const auto& role : members(f.id(), root + "plugins")) {
      const std::string at = root + "plugins/" + role;
      if (role.rfind("diagnostics", 0) != 0) continue;
      const std::string plugin = read_string_attribute(f.id(), at, "plugin");
      const std::string group = root + "diagnostics/" + read_string_attribute(f.id(), at, "instance");
      if (!docs.count(plugin)) docs[plugin] = run_gdsmc({"plugins", plugin}, file.parent_path()).out;
      for (const auto& name : plugin_datasets(f.id(), group))
        EXPECT_TRUE(documents_name(docs[plugin], name))
            << "`gdsmc plugins " << plugin << "` does not name the dataset '" << name << "' of " << group;
    }
  }
}

// The attribute names of `object`.
std::vector<std::string> attribute_names(hid_t file, const std::string& object) {
  if (!exists(file, object)) return {};
  return gdsmc::host::h5::attribute_names(open_object(file, object));
}

// Every `/run/NAME` and `/plugins/ROLE@NAME` the documents cite (NAME may be a family: <stage>,
// *) is an attribute of `file`, a slab run's output.
void expect_cited_attributes_exist(const fs::path& file) {
  const File f(file);
  static const std::regex kCited(R"(`(/run|/plugins/[^`@ ]+)[/@]([^` ]+)`)");
  std::size_t cited = 0;
  for (const auto& doc : documents()) {
    const std::string text = read_text(doc);
    for (auto it = std::sregex_iterator(text.begin(), text.end(), kCited); it != std::sregex_iterator(); ++it) {
      ++cited;
      auto family = [](std::string t) {
        t = std::regex_replace(t, std::regex(R"([.^$|()\[\]{}+?\\])"), "\\$&");
        return std::regex(std::regex_replace(std::regex_replace(t, std::regex("<[a-z_]+>"), ".+"), std::regex("\\*"), ".+"));
      };
      const std::regex object = family((*it)[1]), attribute = family((*it)[2]);
      bool found = false;
      std::vector<std::string> objects{"/run"};
      if ((*it)[1] != "/run") {
        objects.clear();
        for (const auto& role : members(f.id(), "/plugins")) objects.push_back("/plugins/" + role);
      }
      for (const auto& o : objects)
        if (std::regex_match(o, object))
          for (const auto& a : attribute_names(f.id(), o)) found = found || std::regex_match(a, attribute);
      EXPECT_TRUE(found) << fs::relative(doc, source_dir()).string() << " cites " << it->str() << ", which "
                         << file.filename().string() << " does not hold";
    }
  }
  EXPECT_GE(cited, 5u);
}

// The output files in `dir`.
std::vector<fs::path> outputs(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".h5") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

// The extraction itself finds what the documents hold (a test of the test: a parser that found
// nothing would pass every check below).
TEST(Docs, TheSnippetsAreFound) {
  std::size_t yaml = 0, python = 0, cmds = 0;
  for (const auto& f : documents()) {
    const Document d = read_document(f);
    for (const auto& b : d.blocks) yaml += b.lang == "yaml", python += b.lang == "python";
    cmds += commands(d).size();
  }
  EXPECT_GE(yaml, 6u);
  EXPECT_GE(python, 5u);
  EXPECT_GE(cmds, 40u);
  const Document readme = read_document(source_dir() / "README.md");
  bool demo = false;
  for (const auto& b : readme.blocks) demo = demo || (b.lang == "indented" && contains(b.text, "scripts/demo"));
  EXPECT_TRUE(demo) << "the indented block of the README was not found";
  EXPECT_TRUE(is_synopsis(words("run PIPELINE.yaml [--set key.path=value]...")));
  EXPECT_FALSE(is_synopsis(words("run configs/hcs.yaml -o hcs.h5 --set run.particles=2000")));
}

// Every ```yaml block is a pipeline, or a part of one, that `gdsmc validate` accepts.
TEST(Docs, EveryYamlSnippetValidates) {
  for (const auto& f : documents()) {
    const Document d = read_document(f);
    Workdir w;
    for (const auto& b : d.blocks)
      if (b.lang == "yaml") check_yaml(d, b, w.dir.path());
  }
}

// Every gdsmc command line is valid; in a document with h5py recipes its runs run, and the
// recipes then read what the documentation says the files hold.
TEST(Docs, EveryCommandLineAndRecipeWorks) {
  for (const auto& f : documents()) {
    const Document d = read_document(f);
    Workdir w;
    bool recipes = false;
    for (const auto& b : d.blocks) recipes = recipes || b.lang == "python";
    const auto cmds = commands(d);
    // Runs first (the recipes and inspect read their files), then everything else.
    for (const auto& c : cmds)
      if (recipes && words(c.args).size() > 1 && words(c.args)[0] == "run" && !is_synopsis(words(c.args)))
        check_command(d, c, w.dir.path(), true);
    for (const auto& c : cmds)
      if (!(recipes && words(c.args).size() > 1 && words(c.args)[0] == "run" && !is_synopsis(words(c.args))))
        check_command(d, c, w.dir.path(), false);
    for (const auto& b : d.blocks)
      if (b.lang == "python") check_python(d, b, w.dir.path());
    std::map<std::string, std::string> docs;
    for (const auto& file : outputs(w.dir.path())) expect_datasets_documented(file, docs);
  }
}

// The diagnostics the documents' runs do not use name their datasets too: the Poiseuille channel
// (the issue's user had to guess T_centre for T(0)) with the slab diagnostics, the heat flux and
// the Enskog viscosity, each in a run of a second. The /run attributes the documents cite exist in
// the slab run's file.
TEST(Docs, OtherDiagnosticsNameTheirDatasets) {
  TempDir dir;
  const std::vector<std::vector<std::string>> runs = {
      {"configs/poiseuille.yaml", "-o", "poiseuille.h5", "--set", "run.particles=4000", "--set", "run.stop.time=6", "--set",
       "diagnostics=[{plugin: poiseuille_channel, steady_window: 1}, energy_balance, wall_fluxes, slab_averages, profiles, "
       "species_moments]"},
      {"configs/heat_flux.yaml", "-o", "heat_flux.h5", "--set", "run.particles=2000", "--set", "run.stop.time=0.6", "--set",
       "run.average_after.time=0.2"},
      {"configs/enskog_viscosity.yaml", "-o", "enskog.h5", "--set", "run.particles=2000", "--set",
       "run.stop.collisions_per_particle=2", "--set", "run.average_after.collisions_per_particle=1"}};
  for (auto args : runs) {
    args[0] = (source_dir() / args[0]).string();
    args.insert(args.begin(), "run");
    args.push_back("--quiet");
    const ProcessResult r = run_gdsmc(args, dir.path());
    ASSERT_EQ(r.exit_code, 0) << join(args, " ") << "\n" << r.describe();
  }
  std::map<std::string, std::string> docs;
  for (const auto& file : outputs(dir.path())) expect_datasets_documented(file, docs);
  for (const char* plugin : {"poiseuille_channel", "energy_balance", "wall_fluxes", "slab_averages", "profiles", "heat_flux",
                             "enskog_shear_viscosity", "species_moments"})
    EXPECT_TRUE(docs.count(plugin)) << plugin << " was not in the runs";
  EXPECT_TRUE(contains(docs["poiseuille_channel"], "T_centre [T_w] (T(0))")) << docs["poiseuille_channel"];
  expect_cited_attributes_exist(dir / "poiseuille.h5");
}

// docs/performance.md is a reference: the current figures, what limits each and how to reproduce
// them, in at most 200 lines, with the SPARTA deck that its comparison ran; dated series live in
// its history.
TEST(Docs, PerformanceIsAReferenceOfAtMostTwoHundredLines) {
  const std::string text = read_text(source_dir() / "docs" / "performance.md");
  const auto lines = std::count(text.begin(), text.end(), '\n');
  EXPECT_LE(lines, 200) << "docs/performance.md has " << lines << " lines";
  for (const char* part : {"## How to measure", "## Side by side with SPARTA", "create_grid     ${K} ${K} ${K}",
                           "collide         vss gas hs.vss", "## Memory"})
    EXPECT_TRUE(contains(text, part)) << part;
}
