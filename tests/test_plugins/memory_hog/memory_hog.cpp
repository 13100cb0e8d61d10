#include <memory>

#include <gdsmc/gdsmc.hpp>

namespace {

// 1e15 bytes: more than the address space of any x86-64 or arm64 process, so operator new throws
// std::bad_alloc with or without a ulimit.
constexpr std::size_t kTooMuch = 1000000000000000ull;

class MemoryHog final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "memory_hog";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: runs out of memory in begin() or record()";
  static constexpr const char* documentation = "Allocates 1e15 bytes at the stage `at` (std::bad_alloc).";
  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::choice("at", {"begin", "record"}, "when to run out of memory").default_value("record")};
  }
  explicit MemoryHog(const gdsmc::Params& p) : at_begin_(p.string("at") == "begin") {}
  void begin(const gdsmc::SystemInfo&, const gdsmc::QuantityBoard&, gdsmc::OutputSink&) override {
    if (at_begin_) hog_.reset(new char[kTooMuch]);
  }
  void sample(const gdsmc::StepContext&, const gdsmc::ParticleSpan&) override {}
  void record(const gdsmc::StepContext& ctx, gdsmc::OutputSink&) override {
    if (ctx.step > 0) hog_.reset(new char[kTooMuch]);  // after the initial record: the run has started
  }

 private:
  bool at_begin_;
  std::unique_ptr<char[]> hog_;
};

}  // namespace

GDSMC_PLUGIN(MemoryHog)
