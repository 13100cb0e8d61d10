// Test plugin: elastic hard spheres until `after` collisions (counted over the process), then a
// crash inside collide(): SEGV (a write through an invalid pointer), BUS, FPE (raised) or ABRT
// (std::abort, as a failed assert does), or STACK (a stack overflow: SIGSEGV). The host's handler
// must say which plugin crashed.
#include <atomic>
#include <csignal>
#include <cstdint>
#include <cstdlib>

#include <gdsmc/gdsmc.hpp>

namespace {

std::atomic<std::int64_t> g_collisions{0};
volatile std::uintptr_t g_bad_address = 16;  // not known to the compiler: a real fault, not UB it may drop

// Endless recursion that the compiler cannot turn into a loop: a stack overflow (SIGSEGV on the
// stack's guard page, reported only from an alternate signal stack).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Winfinite-recursion"  // the point of it
__attribute__((noinline)) std::uint64_t overflow(std::uint64_t depth) {
  volatile char frame[1024];
  frame[depth % sizeof frame] = static_cast<char>(depth);
  return overflow(depth + 1) + frame[0];
}
#pragma GCC diagnostic pop

struct CrashingRule {
  static constexpr const char* name = "crashing_rule";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: a collision rule that crashes after a number of collisions";
  static constexpr const char* documentation =
      "Elastic hard spheres; the collision numbered `after` (counted over the process) crashes with `signal`: SEGV "
      "writes through an invalid pointer, BUS and FPE raise the signal, ABRT calls std::abort(), STACK recurses "
      "until the stack overflows (SIGSEGV).";
  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::integer("after", "the collisions before the crash").at_least(0).default_value(1000),
            gdsmc::ParamSpec::choice("signal", {"SEGV", "BUS", "FPE", "ABRT", "STACK"}, "how it crashes").default_value("SEGV")};
  }
  explicit CrashingRule(const gdsmc::Params& p) : after(p.integer("after")), how(p.string("signal")) {}
  double collide(gdsmc::Vec3& v1, gdsmc::Vec3& v2, const gdsmc::Vec3& s, gdsmc::PairContext&) const {
    if (g_collisions.fetch_add(1, std::memory_order_relaxed) == after) crash();
    const gdsmc::Vec3 dv = dot(v1 - v2, s) * s;
    v1 -= dv;
    v2 += dv;
    return 0.0;
  }
  void crash() const {
    if (how == "SEGV") *reinterpret_cast<volatile int*>(g_bad_address) = 1;
    else if (how == "BUS") std::raise(SIGBUS);
    else if (how == "FPE") std::raise(SIGFPE);
    else if (how == "STACK") g_bad_address = overflow(0);
    else std::abort();
  }
  std::int64_t after;
  std::string how;
};

}  // namespace

GDSMC_PLUGIN(CrashingRule)
