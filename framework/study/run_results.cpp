#include "study/run_results.hpp"

#include <stdexcept>

namespace gdsmc::host {

namespace {

void write_map(StateWriter& out, const char* name, const std::map<std::string, std::string>& m) {
  out.write(name, static_cast<std::uint64_t>(m.size()));
  for (const auto& [k, v] : m) {
    out.write("key", k);
    out.write("text", v);
  }
}
void write_map(StateWriter& out, const char* name, const std::map<std::string, double>& m) {
  out.write(name, static_cast<std::uint64_t>(m.size()));
  for (const auto& [k, v] : m) {
    out.write("key", k);
    out.write("value", v);
  }
}
std::size_t read_count(StateReader& in, const char* name) {
  std::uint64_t n = 0;
  in.read(name, n);
  if (n > in.remaining()) throw StateError(std::string("run results: '") + name + "' counts more entries than the bytes hold");
  return static_cast<std::size_t>(n);
}
template <class Value>
void read_map(StateReader& in, const char* name, const char* value_name, std::map<std::string, Value>& m) {
  m.clear();
  for (std::size_t k = read_count(in, name); k > 0; --k) {
    std::string key;
    Value value{};
    in.read("key", key);
    in.read(value_name, value);
    m[key] = value;
  }
}

// A diagnostic's records: the names it declared first (as its begin() would, which load() checks),
// then everything DiagnosticOutput::save writes.
void write_diagnostic(StateWriter& out, const DiagnosticOutput& d) {
  out.write("group", d.group());
  out.write("declared_columns", static_cast<std::uint64_t>(d.columns.size()));
  for (const auto& c : d.columns) out.write("name", c.name);
  out.write("declared_profiles", static_cast<std::uint64_t>(d.profiles.size()));
  for (const auto& p : d.profiles) out.write("name", p.name);
  d.save(out);
}
DiagnosticOutput read_diagnostic(StateReader& in) {
  std::string group;
  in.read("group", group);
  DiagnosticOutput d(group, nullptr);
  d.columns.resize(read_count(in, "declared_columns"));
  for (auto& c : d.columns) in.read("name", c.name);
  d.profiles.resize(read_count(in, "declared_profiles"));
  for (auto& p : d.profiles) in.read("name", p.name);
  d.load(in);
  return d;
}

}  // namespace

std::vector<unsigned char> save_run_results(const RunResults& r) {
  BufferStateWriter out;
  out.write("collisions", r.collisions);
  out.write("wall_seconds", r.wall_seconds);
  out.write("stage_seconds", r.stage_seconds.data(), r.stage_seconds.size());
  out.write("steps", r.steps);
  out.write("steady", static_cast<std::uint8_t>(r.steady));
  out.write("summary", static_cast<std::uint64_t>(r.summary.size()));
  for (const auto& line : r.summary) out.write("line", line);
  out.write("diagnostics", static_cast<std::uint64_t>(r.diagnostics.size()));
  for (const auto& d : r.diagnostics) write_diagnostic(out, d);
  out.write("output", static_cast<std::uint8_t>(r.output.has_value()));
  if (r.output) {
    const CaseOutput& c = *r.output;
    out.write("group", c.group);
    write_map(out, "attributes", c.attributes);
    write_map(out, "system", c.system);
    write_map(out, "run", c.run);
    out.write("plugins", static_cast<std::uint64_t>(c.plugins.size()));
    for (const auto& p : c.plugins) {
      for (const std::string* text : {&p.role, &p.instance, &p.plugin, &p.version, &p.file, &p.library_hash}) out.write("text", *text);
      write_map(out, "parameters", p.parameters);
    }
    out.write("particles", static_cast<std::uint64_t>(c.particles.size()));
    for (const auto& d : c.particles) {
      if (!d.staged.empty())
        throw std::logic_error("run results: particle dataset '" + d.name + "' is staged in " + d.staged +
                               ", not held in memory");
      for (const std::string* text : {&d.name, &d.unit, &d.doc}) out.write("text", *text);
      out.write("components", static_cast<std::int32_t>(d.components));
      out.write("data", d.data);
    }
    out.write("system_arrays", static_cast<std::uint64_t>(c.system_arrays.size()));
    for (const auto& d : c.system_arrays) {
      for (const std::string* text : {&d.name, &d.unit, &d.doc}) out.write("text", *text);
      out.write("data", d.data);
    }
  }
  return out.take();
}

RunResults load_run_results(const std::vector<unsigned char>& bytes) {
  BufferStateReader in(bytes);
  RunResults r;
  in.read("collisions", r.collisions);
  in.read("wall_seconds", r.wall_seconds);
  in.read("stage_seconds", r.stage_seconds.data(), r.stage_seconds.size());
  in.read("steps", r.steps);
  std::uint8_t flag = 0;
  in.read("steady", flag);
  r.steady = flag != 0;
  r.summary.resize(read_count(in, "summary"));
  for (auto& line : r.summary) in.read("line", line);
  for (std::size_t k = read_count(in, "diagnostics"); k > 0; --k) r.diagnostics.push_back(read_diagnostic(in));
  in.read("output", flag);
  if (flag) {
    CaseOutput& c = r.output.emplace();
    in.read("group", c.group);
    read_map(in, "attributes", "text", c.attributes);
    read_map(in, "system", "value", c.system);
    read_map(in, "run", "value", c.run);
    c.plugins.resize(read_count(in, "plugins"));
    for (auto& p : c.plugins) {
      for (std::string* text : {&p.role, &p.instance, &p.plugin, &p.version, &p.file, &p.library_hash}) in.read("text", *text);
      read_map(in, "parameters", "text", p.parameters);
    }
    c.particles.resize(read_count(in, "particles"));
    for (auto& d : c.particles) {
      for (std::string* text : {&d.name, &d.unit, &d.doc}) in.read("text", *text);
      std::int32_t components = 1;
      in.read("components", components);
      d.components = components;
      in.read("data", d.data);
    }
    c.system_arrays.resize(read_count(in, "system_arrays"));
    for (auto& d : c.system_arrays) {
      for (std::string* text : {&d.name, &d.unit, &d.doc}) in.read("text", *text);
      in.read("data", d.data);
    }
  }
  if (!in.at_end()) throw StateError("run results: " + std::to_string(in.remaining()) + " bytes left after the results");
  return r;
}

}  // namespace gdsmc::host
