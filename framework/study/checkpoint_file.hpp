// The files of a checkpoint (study/checkpoint.hpp): the SDK's state entries, each with a
// checksum, written straight into a file (FileStateWriter) and read back only once every entry
// has been checked against its checksum (FileStateReader). Internal to the checkpoint store.
#pragma once
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <gdsmc/state.hpp>

#include "util/content_hash.hpp"

namespace gdsmc::host {

// Follows the SDK's entry framing through a stream of bytes, hashing each entry.
class EntryScanner {
 public:
  // Feeds bytes; `done(name, begin, end, hash)` is called at the end of each entry (bytes
  // [begin, end) of the stream). A header that cannot be (a name longer than the SDK allows)
  // makes feed() return false.
  template <class Done>
  bool feed(const unsigned char* p, std::size_t n, Done&& done) {
    while (n) {
      std::size_t take = 0;
      switch (phase_) {
        case Phase::length:
        case Phase::tail: {
          const std::size_t want = (phase_ == Phase::length ? 4 : 10) - have_;
          take = std::min(want, n);
          std::memcpy(head_ + have_, p, take);
          have_ += take;
          if (take == want) {
            if (phase_ == Phase::length) {
              std::uint32_t length;
              std::memcpy(&length, head_, 4);
              if (length > 4096) {
                hash_.update(p, take);
                return false;
              }
              name_.clear();
              left_ = length;
              phase_ = Phase::name;
            } else {
              std::uint64_t count;
              std::memcpy(&count, head_ + 2, 8);
              const unsigned size = head_[1];
              left_ = size && count > ~std::uint64_t{0} / size ? ~std::uint64_t{0} : count * size;
              phase_ = Phase::payload;
            }
            have_ = 0;
          }
          break;
        }
        case Phase::name:
          take = static_cast<std::size_t>(std::min<std::uint64_t>(left_, n));
          name_.append(reinterpret_cast<const char*>(p), take);
          left_ -= take;
          if (!left_) phase_ = Phase::tail;
          break;
        case Phase::payload:
          take = static_cast<std::size_t>(std::min<std::uint64_t>(left_, n));
          left_ -= take;
          break;
      }
      hash_.update(p, take);
      at_ += take;
      p += take;
      n -= take;
      if (phase_ == Phase::payload && !left_) end_entry(done);
    }
    if (phase_ == Phase::payload && !left_) end_entry(done);  // an entry without payload
    return true;
  }
  // Between entries (not inside one).
  bool at_boundary() const { return phase_ == Phase::length && have_ == 0; }
  const std::string& name() const { return name_; }    // of the entry under way
  std::uint64_t entry_begin() const { return begin_; }  // its first byte
  std::uint64_t payload_left() const { return phase_ == Phase::payload ? left_ : 0; }

 private:
  enum class Phase { length, name, tail, payload };
  template <class Done>
  void end_entry(Done&& done) {
    done(name_, begin_, at_, hash_.finish());
    hash_.reset();
    phase_ = Phase::length;
    have_ = 0;
    begin_ = at_;
  }
  Phase phase_ = Phase::length;
  unsigned char head_[10] = {};
  std::size_t have_ = 0;
  std::uint64_t left_ = 0, at_ = 0, begin_ = 0;
  std::string name_;
  ContentHash hash_;
};

// Entries straight into a file (a state of 10^7 particles is never held twice in memory), each
// with its checksum in the table at the end.
class FileStateWriter final : public StateWriter {
 public:
  explicit FileStateWriter(const std::filesystem::path& path);
  ~FileStateWriter() override;
  // The checksum table, then flush, fsync and close; throws on any error (disk full).
  void close();

 protected:
  void put(const void* data, std::size_t bytes) override;

 private:
  void raw(const void* data, std::size_t bytes);
  std::filesystem::path path_;
  std::FILE* file_ = nullptr;
  EntryScanner scanner_;
  std::vector<std::uint64_t> sums_;
  std::uint64_t bytes_ = 0;
};

// The entries of a file that passed its checksums. Opening reads the whole file once to check
// every entry against the table (CheckpointError naming the file and the entry); reads then
// serve the entries alone. Without `verify` (a file already checked, read again for a message:
// describe, kept_text) only the table's tail is checked.
enum class Verify { all, tail };
class FileStateReader final : public StateReader {
 public:
  explicit FileStateReader(const std::filesystem::path& path, Verify verify = Verify::all);
  ~FileStateReader() override;
  std::string peek_name() override;
  std::uint64_t remaining() const override { return size_ - at_; }
  bool at_end() const { return at_ == size_; }
  std::size_t entries() const { return entries_; }

 protected:
  void get(void* data, std::size_t bytes) override;

 private:
  [[noreturn]] void damaged(const std::string& what) const;
  void read_at(std::uint64_t offset, void* data, std::size_t bytes);
  void check(Verify verify);
  std::filesystem::path path_;
  std::FILE* file_ = nullptr;
  std::uint64_t size_ = 0, at_ = 0;
  std::size_t entries_ = 0;
};

}  // namespace gdsmc::host
