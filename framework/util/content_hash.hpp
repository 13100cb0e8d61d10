// A 64-bit hash of a stream of bytes, for telling contents apart: each checkpoint entry's
// checksum and each plugin library's identity. Not cryptographic. Four lanes take the 8-byte
// words of each 32-byte block (word * K1, xor, rotate, * K2 + K3: every step is a bijection of
// the word and of the lane), so a change confined to one word, a flipped bit among them, always
// changes the hash; the tail and the length are mixed in at the end. The result does not depend
// on how the bytes are split between update() calls. About 8 GB/s on one core (user-guide.md,
// "Checkpoints and resuming").
#pragma once
#include <cerrno>
#include <cstddef>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>

namespace gdsmc::host {

class ContentHash {
 public:
  void update(const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    length_ += bytes;
    if (pending_) {  // complete the block begun by an earlier call
      const std::size_t take = bytes < kBlock - pending_ ? bytes : kBlock - pending_;
      std::memcpy(buffer_ + pending_, p, take);
      pending_ += take;
      p += take;
      bytes -= take;
      if (pending_ < kBlock) return;
      block(buffer_);
      pending_ = 0;
    }
    for (; bytes >= kBlock; p += kBlock, bytes -= kBlock) block(p);
    std::memcpy(buffer_, p, bytes);
    pending_ = bytes;
  }
  std::uint64_t finish() const {
    std::uint64_t h = kSeed;
    for (std::uint64_t v : lane_) h = mix(h, v);
    std::size_t at = 0;
    for (; at + 8 <= pending_; at += 8) h = mix(h, word(buffer_ + at));
    if (at < pending_) {
      unsigned char last[8] = {};
      std::memcpy(last, buffer_ + at, pending_ - at);
      h = mix(h, word(last));
    }
    h = mix(h, length_);
    h ^= h >> 31;  // splitmix64's finaliser: a bijection spreading every bit over the result
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 27;
    h *= 0x94D049BB133111EBull;
    return h ^ (h >> 31);
  }
  void reset() { *this = ContentHash(); }

  // 16 hexadecimal digits.
  static std::string hex(std::uint64_t h) {
    static const char* digits = "0123456789abcdef";
    std::string s(16, '0');
    for (int k = 15; k >= 0; --k, h >>= 4) s[static_cast<std::size_t>(k)] = digits[h & 15];
    return s;
  }

 private:
  static constexpr std::size_t kBlock = 32;
  static constexpr std::uint64_t kSeed = 0x6764736D63686B31ull;  // "gdsmchk1"
  static std::uint64_t word(const unsigned char* p) {
    std::uint64_t w;
    std::memcpy(&w, p, 8);
    return w;
  }
  static std::uint64_t mix(std::uint64_t h, std::uint64_t w) {
    h ^= w * 0x9E3779B97F4A7C15ull;
    h = (h << 29) | (h >> 35);
    return h * 0xC2B2AE3D27D4EB4Full + 0x165667B19E3779F9ull;
  }
  void block(const unsigned char* p) {
    for (int k = 0; k < 4; ++k) lane_[k] = mix(lane_[k], word(p + 8 * k));
  }
  std::uint64_t lane_[4] = {kSeed, kSeed ^ 1, kSeed ^ 2, kSeed ^ 3};
  unsigned char buffer_[kBlock] = {};
  std::size_t pending_ = 0;
  std::uint64_t length_ = 0;
};

// The hash of a file's bytes (a plugin library). Throws std::runtime_error naming the file.
inline std::uint64_t file_content_hash(const std::filesystem::path& file) {
  std::FILE* f = std::fopen(file.c_str(), "rb");
  if (!f) throw std::runtime_error("cannot read " + file.string() + ": " + std::strerror(errno));
  ContentHash h;
  static thread_local unsigned char buffer[1 << 16];
  std::size_t got;
  while ((got = std::fread(buffer, 1, sizeof buffer, f)) > 0) h.update(buffer, got);
  const bool failed = std::ferror(f) != 0;
  const int saved = errno;
  std::fclose(f);
  if (failed) throw std::runtime_error("cannot read " + file.string() + ": " + std::strerror(saved));
  return h.finish();
}

}  // namespace gdsmc::host
