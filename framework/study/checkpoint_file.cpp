// The checksummed files of a checkpoint: FileStateWriter writes the SDK's entries and the table
// of their checksums, FileStateReader checks a whole file against its table before it reads.
#include "study/checkpoint_file.hpp"

#include <unistd.h>

#include <cerrno>

#include "study/checkpoint.hpp"

namespace gdsmc::host {

namespace fs = std::filesystem;

namespace {

std::string errno_text() { return std::strerror(errno); }

// Every entry of a checkpoint file carries a checksum. The file is the entries as the SDK's
// StateWriter frames them (name length, name, kind, element size, count, payload), then a table:
// one 64-bit ContentHash per entry, over the entry's bytes (header and payload), then the entry
// count, the bytes of the entries, the table's own hash and the 8 bytes "GDSMCSUM". The reader
// checks the whole file against its table before it hands out a byte, so a flipped bit, a
// truncated file or a file still being written is refused naming the file and the entry. The
// checksums live entirely in the host's file writer and reader: the SDK's entry format and ABI are
// unchanged (a plugin's own entries travel inside the host's entry "plugin.<role>").
constexpr char kTableMagic[8] = {'G', 'D', 'S', 'M', 'C', 'S', 'U', 'M'};
constexpr std::uint64_t kTableTail = 32;  // count, entry bytes, table hash, magic

}  // namespace

FileStateWriter::FileStateWriter(const fs::path& path) : path_(path) {
  file_ = std::fopen(path.c_str(), "wb");
  if (!file_) throw std::runtime_error("cannot create " + path.string() + ": " + errno_text());
  std::setvbuf(file_, nullptr, _IOFBF, 1 << 20);
}

FileStateWriter::~FileStateWriter() {
  if (file_) std::fclose(file_);
}

void FileStateWriter::close() {
  if (!scanner_.at_boundary()) throw std::logic_error("checkpoint " + path_.string() + ": an entry was left unfinished");
  ContentHash table;
  const std::uint64_t tail[2] = {static_cast<std::uint64_t>(sums_.size()), bytes_};
  raw(sums_.data(), sums_.size() * sizeof(std::uint64_t));
  raw(tail, sizeof tail);
  table.update(sums_.data(), sums_.size() * sizeof(std::uint64_t));
  table.update(tail, sizeof tail);
  const std::uint64_t table_hash = table.finish();
  raw(&table_hash, sizeof table_hash);
  raw(kTableMagic, sizeof kTableMagic);
  const bool ok = std::fflush(file_) == 0 && ::fsync(::fileno(file_)) == 0;
  const int saved = errno;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!ok || !closed) {
    errno = ok ? errno : saved;
    throw std::runtime_error("cannot write " + path_.string() + ": " + errno_text());
  }
}

void FileStateWriter::put(const void* data, std::size_t bytes) {
  raw(data, bytes);
  bytes_ += bytes;
  scanner_.feed(static_cast<const unsigned char*>(data), bytes,
                [&](const std::string&, std::uint64_t, std::uint64_t, std::uint64_t hash) { sums_.push_back(hash); });
}

void FileStateWriter::raw(const void* data, std::size_t bytes) {
  if (bytes && std::fwrite(data, 1, bytes, file_) != bytes)
    throw std::runtime_error("cannot write " + path_.string() + ": " + errno_text());
}

FileStateReader::FileStateReader(const fs::path& path, Verify verify) : path_(path) {
  file_ = std::fopen(path.c_str(), "rb");
  if (!file_) throw CheckpointError("cannot read " + path.string() + ": " + errno_text());
  std::setvbuf(file_, nullptr, _IOFBF, 1 << 20);
  check(verify);
}

FileStateReader::~FileStateReader() { std::fclose(file_); }

std::string FileStateReader::peek_name() {
  const long at = std::ftell(file_);
  std::uint32_t length = 0;
  std::string name;
  if (remaining() >= sizeof length && std::fread(&length, sizeof length, 1, file_) == 1 && length <= 4096 &&
      length <= remaining()) {
    name.resize(length);
    if (std::fread(name.data(), 1, length, file_) != length) name.clear();
  }
  std::fseek(file_, at, SEEK_SET);
  return name;
}

void FileStateReader::get(void* data, std::size_t bytes) {
  if (bytes > remaining() || std::fread(data, 1, bytes, file_) != bytes)
    throw StateError(path_.string() + " is truncated (" + std::to_string(bytes) + " bytes wanted, " +
                     std::to_string(remaining()) + " left)");
  at_ += bytes;
}

void FileStateReader::damaged(const std::string& what) const {
  throw CheckpointError(path_.string() + " is damaged: " + what +
                        "; it cannot be used (a bit changed on disk or in a copy, or the file was cut short)");
}

void FileStateReader::read_at(std::uint64_t offset, void* data, std::size_t bytes) {
  if (std::fseek(file_, static_cast<long>(offset), SEEK_SET) != 0 || std::fread(data, 1, bytes, file_) != bytes)
    throw CheckpointError("cannot read " + path_.string() + ": " + errno_text());
}

void FileStateReader::check(Verify verify) {
  std::error_code ec;
  const std::uint64_t file_size = fs::file_size(path_, ec);
  if (ec) throw CheckpointError("cannot read " + path_.string() + ": " + ec.message());
  char magic[8] = {};
  std::uint64_t tail[3] = {};  // entries, entry bytes, table hash
  if (file_size >= kTableTail) {
    read_at(file_size - kTableTail, tail, sizeof tail);
    read_at(file_size - sizeof magic, magic, sizeof magic);
  }
  if (file_size < kTableTail || std::memcmp(magic, kTableMagic, sizeof magic) != 0)
    throw CheckpointError(path_.string() + " is truncated or not a checkpoint file of this gdsmc: it does not end with "
                          "its table of checksums (" + std::to_string(file_size) +
                          " bytes); it cannot be used (a write cut short, a file cut in a copy, or a checkpoint "
                          "of an older gdsmc, which had no checksums)");
  const std::uint64_t count = tail[0], bytes = tail[1];
  if (count > file_size / 8 || bytes > file_size || bytes + 8 * count + kTableTail != file_size)
    damaged("its table of checksums claims " + std::to_string(count) + " entries in " + std::to_string(bytes) +
            " bytes, which does not fit its " + std::to_string(file_size) + " bytes");
  if (verify == Verify::tail) {
    if (std::fseek(file_, 0, SEEK_SET) != 0) throw CheckpointError("cannot read " + path_.string() + ": " + errno_text());
    size_ = bytes;
    entries_ = count;
    return;
  }
  std::vector<std::uint64_t> sums(count);
  if (count) read_at(bytes, sums.data(), count * 8);
  ContentHash table;
  table.update(sums.data(), count * 8);
  table.update(tail, 16);
  if (table.finish() != tail[2]) damaged("its table of checksums does not match its own checksum");
  // Every entry against its checksum.
  if (std::fseek(file_, 0, SEEK_SET) != 0) throw CheckpointError("cannot read " + path_.string() + ": " + errno_text());
  EntryScanner scanner;
  std::vector<unsigned char> buffer(1 << 20);
  std::size_t entry = 0;
  auto done = [&](const std::string& name, std::uint64_t begin, std::uint64_t end, std::uint64_t hash) {
    if (entry >= count)
      damaged("entry " + std::to_string(entry + 1) + " '" + name + "' (at byte " + std::to_string(begin) +
              ") is beyond the " + std::to_string(count) + " entries its table lists");
    if (hash != sums[entry])
      damaged("entry " + std::to_string(entry + 1) + " of " + std::to_string(count) + ", '" + name + "' (bytes " +
              std::to_string(begin) + " to " + std::to_string(end) +
              "), does not match its checksum");
    ++entry;
  };
  at_ = 0;
  for (std::uint64_t left = bytes; left;) {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(left, buffer.size()));
    if (std::fread(buffer.data(), 1, n, file_) != n) throw CheckpointError("cannot read " + path_.string() + ": " + errno_text());
    if (!scanner.feed(buffer.data(), n, done))
      damaged("entry " + std::to_string(entry + 1) + " (at byte " + std::to_string(scanner.entry_begin()) +
              ") has a damaged header");
    if (scanner.payload_left() > left - n)
      damaged("entry " + std::to_string(entry + 1) + ", '" + scanner.name() + "' (at byte " +
              std::to_string(scanner.entry_begin()) + "), claims more bytes than the file holds");
    left -= n;
  }
  if (!scanner.at_boundary() || entry != count)
    damaged("its entries end inside entry " + std::to_string(entry + 1) + " of the " + std::to_string(count) +
            " its table lists");
  if (std::fseek(file_, 0, SEEK_SET) != 0) throw CheckpointError("cannot read " + path_.string() + ": " + errno_text());
  size_ = bytes;
  entries_ = count;
}

}  // namespace gdsmc::host
