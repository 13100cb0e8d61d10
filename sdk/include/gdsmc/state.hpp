// gdsmc SDK: what a plugin writes into a checkpoint and reads back on resume
// (PluginObject::save_state / load_state). A checkpoint is a sequence of named entries: a number,
// an array of numbers or a text. The reader asks for them by name in the order they were written,
// and a name, type or length that does not match is a StateError that names both, so a plugin that
// changed what it saves refuses an old checkpoint instead of reading garbage.
#pragma once
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace gdsmc {

class StateError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

namespace detail {
// The type of an entry: its kind and its element size.
enum class StateKind : std::uint8_t { floating = 1, signed_integer = 2, unsigned_integer = 3, text = 4 };
template <class T>
constexpr StateKind state_kind() {
  if constexpr (std::is_floating_point_v<T>) return StateKind::floating;
  else if constexpr (std::is_signed_v<T>) return StateKind::signed_integer;
  else return StateKind::unsigned_integer;
}
inline const char* state_kind_text(StateKind k, std::uint8_t size) {
  switch (k) {
    case StateKind::floating: return size == 4 ? "float" : "double";
    case StateKind::signed_integer: return "signed integer";
    case StateKind::unsigned_integer: return size == 1 ? "unsigned byte or bool" : "unsigned integer";
    case StateKind::text: return "text";
  }
  return "unknown";
}
template <class T>
concept StateNumber = std::is_arithmetic_v<T>;
}  // namespace detail

// Writes entries. The host gives a plugin one writer per checkpoint; the bytes go where the host
// says (a file, a buffer).
class StateWriter {
 public:
  virtual ~StateWriter() = default;

  template <detail::StateNumber T>
  void write(std::string_view name, const T& value) { write(name, &value, 1); }
  template <detail::StateNumber T>
  void write(std::string_view name, const std::vector<T>& values) { write(name, values.data(), values.size()); }
  template <detail::StateNumber T>
  void write(std::string_view name, const T* values, std::size_t count) {
    header(name, detail::state_kind<T>(), sizeof(T), count);
    if (count) put(values, count * sizeof(T));
  }
  void write(std::string_view name, const std::string& text) {
    header(name, detail::StateKind::text, 1, text.size());
    if (!text.empty()) put(text.data(), text.size());
  }
  void write(std::string_view name, const char* text) { write(name, std::string(text)); }

 protected:
  virtual void put(const void* data, std::size_t bytes) = 0;

 private:
  void header(std::string_view name, detail::StateKind kind, std::size_t size, std::size_t count) {
    const auto length = static_cast<std::uint32_t>(name.size());
    const auto k = static_cast<std::uint8_t>(kind), s = static_cast<std::uint8_t>(size);
    const auto n = static_cast<std::uint64_t>(count);
    put(&length, sizeof length);
    put(name.data(), name.size());
    put(&k, 1);
    put(&s, 1);
    put(&n, sizeof n);
  }
};

// Reads entries back, in the order they were written. Every read checks the entry's name, type
// and (for a fixed-size destination) length.
class StateReader {
 public:
  virtual ~StateReader() = default;

  template <detail::StateNumber T>
  void read(std::string_view name, T& value) { read(name, &value, 1); }
  template <detail::StateNumber T>
  void read(std::string_view name, std::vector<T>& values) {
    const std::uint64_t n = header(name, detail::state_kind<T>(), sizeof(T));
    if (n > remaining() / sizeof(T)) fail(name, "an array longer than the checkpoint");
    values.resize(static_cast<std::size_t>(n));
    if (n) get(values.data(), values.size() * sizeof(T));
  }
  // Exactly `count` values into `values`.
  template <detail::StateNumber T>
  void read(std::string_view name, T* values, std::size_t count) {
    const std::uint64_t n = header(name, detail::state_kind<T>(), sizeof(T));
    if (n != count)
      fail(name, std::to_string(n) + " values where " + std::to_string(count) + " are expected");
    if (n) get(values, count * sizeof(T));
  }
  void read(std::string_view name, std::string& text) {
    const std::uint64_t n = header(name, detail::StateKind::text, 1);
    if (n > remaining()) fail(name, "a text longer than the checkpoint");
    text.resize(static_cast<std::size_t>(n));
    if (n) get(text.data(), text.size());
  }
  // The name of the next entry, without consuming it ("" at the end).
  virtual std::string peek_name() = 0;
  // Bytes left (an upper bound for what a length may claim).
  virtual std::uint64_t remaining() const = 0;

 protected:
  // Reads exactly `bytes` bytes or throws StateError (a truncated checkpoint).
  virtual void get(void* data, std::size_t bytes) = 0;
  [[noreturn]] void fail(std::string_view name, const std::string& what) const {
    throw StateError("checkpoint entry '" + std::string(name) + "': " + what);
  }

 private:
  std::uint64_t header(std::string_view name, detail::StateKind kind, std::size_t size) {
    std::uint32_t length = 0;
    get(&length, sizeof length);
    if (length > 4096 || length > remaining()) fail(name, "a damaged entry (name length " + std::to_string(length) + ")");
    std::string found(length, '\0');
    if (length) get(found.data(), length);
    std::uint8_t k = 0, s = 0;
    std::uint64_t n = 0;
    get(&k, 1);
    get(&s, 1);
    get(&n, sizeof n);
    if (found != name) fail(name, "the checkpoint has '" + found + "' here (saved by another version?)");
    if (k != static_cast<std::uint8_t>(kind) || s != size)
      fail(name, std::string("saved as ") + detail::state_kind_text(static_cast<detail::StateKind>(k), s) +
                     " of " + std::to_string(s) + " bytes, read as " + detail::state_kind_text(kind, static_cast<std::uint8_t>(size)) +
                     " of " + std::to_string(size) + " bytes");
    return n;
  }
};

// A writer into memory and a reader from memory (checkpoints of plugins, tests, conformance).
class BufferStateWriter final : public StateWriter {
 public:
  const std::vector<unsigned char>& bytes() const { return bytes_; }
  std::vector<unsigned char> take() { return std::move(bytes_); }

 protected:
  void put(const void* data, std::size_t bytes) override {
    const auto* p = static_cast<const unsigned char*>(data);
    bytes_.insert(bytes_.end(), p, p + bytes);
  }

 private:
  std::vector<unsigned char> bytes_;
};

class BufferStateReader final : public StateReader {
 public:
  BufferStateReader(const unsigned char* data, std::size_t size) : data_(data), size_(size) {}
  explicit BufferStateReader(const std::vector<unsigned char>& bytes) : BufferStateReader(bytes.data(), bytes.size()) {}
  bool at_end() const { return at_ == size_; }
  std::string peek_name() override {
    std::uint32_t length = 0;
    if (size_ - at_ < sizeof length) return "";
    std::memcpy(&length, data_ + at_, sizeof length);
    if (length > size_ - at_ - sizeof length) return "";
    return std::string(reinterpret_cast<const char*>(data_ + at_ + sizeof length), length);
  }
  std::uint64_t remaining() const override { return size_ - at_; }

 protected:
  void get(void* data, std::size_t bytes) override {
    if (bytes > size_ - at_) throw StateError("checkpoint: truncated state (" + std::to_string(bytes) + " bytes wanted, " +
                                              std::to_string(size_ - at_) + " left)");
    std::memcpy(data, data_ + at_, bytes);
    at_ += bytes;
  }

 private:
  const unsigned char* data_;
  std::size_t size_, at_ = 0;
};

}  // namespace gdsmc
