#pragma once
// Private: a bounds-checked cursor over an in-memory file, with text (token/line) and binary
// (endian-aware) reads. Every failure throws isoforge::Error naming the file and the place
// (line for text, byte offset for binary). Used by every reader.

#include <algorithm>
#include <atomic>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "isoforge/core/error.hpp"
#include "isoforge/core/parallel.hpp"
#include "file_source.hpp"
#include "progress.hpp"
#include "tuple_stream.hpp"

namespace isoforge::io_detail {

enum class Endian { Little, Big };

inline constexpr Endian kHostEndian =
    std::endian::native == std::endian::little ? Endian::Little : Endian::Big;

template <class T>
inline T byteswap_value(T v) {
  static_assert(std::is_trivially_copyable_v<T>);
  unsigned char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  std::reverse(b, b + sizeof(T));
  std::memcpy(&v, b, sizeof(T));
  return v;
}


/// File content shown in an error message: at most `max` bytes, "..." when cut, and every byte
/// outside printable ASCII as \xNN — a NUL would end the message, an escape sequence would
/// reach the terminal.
inline std::string printable(std::string_view text, std::size_t max = 40) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string s;
  for (const char c : text.substr(0, max)) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u < 0x7f) {
      s += c;
    } else {
      s += "\\x";
      s += kHex[u >> 4];
      s += kHex[u & 15];
    }
  }
  if (text.size() > max) s += "...";
  return s;
}
/// `printable` in single quotes.
inline std::string quoted(std::string_view text, std::size_t max = 40) {
  return "'" + printable(text, max) + "'";
}

/// Whether `c` is ASCII white space (the C locale's isspace).
inline bool is_ascii_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v';
}

/// `s` without its leading and trailing ASCII white space.
inline std::string_view trim_space(std::string_view s) {
  while (!s.empty() && is_ascii_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_ascii_space(s.back())) s.remove_suffix(1);
  return s;
}

/// `s` with its ASCII letters lowered (locale-independent).
inline std::string ascii_lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return out;
}

/// Appends the shortest decimal text that reads back as `v` (std::to_chars).
template <class T>
inline void append_number(std::string& out, T v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof(buf), v);
  out.append(buf, r.ptr);
}

/// Parses a whole token as a number of type T (a leading '+' allowed; nan/inf spellings as
/// from_chars takes them; a float out of range becomes what strtod makes of it: inf or 0);
/// false if the token is not a valid T. Every reader's number syntax.
template <class T>
bool parse_number(std::string_view t, T& value) {
  const char* b = t.data();
  const char* e = t.data() + t.size();
  if (b != e && *b == '+') ++b;
  if (b == e) return false;
  const auto [p, ec] = std::from_chars(b, e, value);
  if constexpr (std::is_floating_point_v<T>) {
    if (ec == std::errc::result_out_of_range && p == e) {
      value = static_cast<T>(std::strtod(std::string(b, e).c_str(), nullptr));
      return true;
    }
  }
  return ec == std::errc() && p == e;
}

/// What `parse_numbers` did: bytes of `text` up to the end of the last token, the newlines in
/// them, the tokens parsed (< count at the end of the text), and whether one was not a number.
struct ParsedNumbers {
  std::size_t end = 0;
  std::int64_t lines = 0;
  std::size_t found = 0;
  bool bad = false;
};

/// Parses the first `count` white-space separated numbers of `text` into `out`, in parallel:
/// the text is cut into 1 MiB pieces (a token belongs to the piece it starts in), the tokens of
/// a batch of pieces are counted on all threads, then each piece parses its own at the index
/// the counts give. The result does not depend on the thread count. `parse(token, value)` is
/// the format's own number syntax (default: parse_number's).
template <class T, class Parse = bool (*)(std::string_view, T&)>
ParsedNumbers parse_numbers(std::string_view text, std::size_t count, T* out,
                            Parse parse = &parse_number<T>) {
  constexpr std::size_t kPiece = std::size_t{1} << 20;
  constexpr std::size_t kBatch = 16;  // pieces counted and parsed together
  const auto space = [](char c) { return is_ascii_space(c); };
  ParsedNumbers r;
  std::size_t pos = 0;
  std::atomic<bool> bad{false};
  while (r.found < count && pos < text.size()) {
    const std::size_t np = std::min(kBatch, (text.size() - pos + kPiece - 1) / kPiece);
    std::vector<std::size_t> first(np), tokens(np), last_end(np);
    const auto piece_begin = [&](std::size_t k) {
      std::size_t s = pos + k * kPiece;
      if (s > 0 && !space(text[s - 1])) {  // inside a token of the piece before
        while (s < text.size() && !space(text[s])) ++s;
      }
      return s;
    };
    const auto piece_end = [&](std::size_t k) { return std::min(text.size(), pos + (k + 1) * kPiece); };
    parallel_for_range(np, 1, [&](std::size_t b, std::size_t e) {
      for (std::size_t k = b; k < e; ++k) {
        std::size_t i = piece_begin(k), n = 0;
        const std::size_t stop = piece_end(k);
        first[k] = i;
        while (true) {
          while (i < stop && space(text[i])) ++i;
          if (i >= stop) break;
          ++n;
          while (i < text.size() && !space(text[i])) ++i;
        }
        tokens[k] = n;
      }
    });
    std::vector<std::size_t> at(np + 1, r.found);
    for (std::size_t k = 0; k < np; ++k) at[k + 1] = at[k] + tokens[k];
    parallel_for_range(np, 1, [&](std::size_t b, std::size_t e) {
      for (std::size_t k = b; k < e; ++k) {
        std::size_t i = first[k], idx = at[k], end = first[k];
        const std::size_t stop = piece_end(k);
        while (idx < count) {
          while (i < stop && space(text[i])) ++i;
          if (i >= stop) break;
          const std::size_t t0 = i;
          while (i < text.size() && !space(text[i])) ++i;
          if (!parse(text.substr(t0, i - t0), out[idx])) bad.store(true);
          ++idx;
          end = i;
        }
        last_end[k] = end;
      }
    });
    for (std::size_t k = 0; k < np; ++k) {
      if (at[k] < count && tokens[k] > 0) r.end = last_end[k];
    }
    r.found = std::min(count, at[np]);
    pos = piece_end(np - 1);
  }
  r.bad = bad.load();
  // Lines in the consumed text, for the scanner's line count.
  const std::size_t pieces = (r.end + kPiece - 1) / kPiece;
  std::vector<std::int64_t> nl(pieces, 0);
  parallel_for_range(pieces, 1, [&](std::size_t b, std::size_t e) {
    for (std::size_t k = b; k < e; ++k) {
      const std::size_t lo = k * kPiece, hi = std::min(r.end, lo + kPiece);
      nl[k] = std::count(text.begin() + static_cast<std::ptrdiff_t>(lo),
                         text.begin() + static_cast<std::ptrdiff_t>(hi), '\n');
    }
  });
  for (const auto n : nl) r.lines += n;
  return r;
}

class Scanner {
 public:
  /// `source`: the bytes (and the file they are mapped from, whose arrays read_array copies
  /// with pread; file_source.hpp).
  Scanner(FileSource source, std::string name)
      : source_(source), data_(source.bytes), name_(std::move(name)) {}

  [[nodiscard]] const std::string& name() const { return name_; }
  [[nodiscard]] std::size_t offset() const { return pos_; }
  [[nodiscard]] std::size_t size() const { return data_.size(); }
  [[nodiscard]] std::size_t remaining() const { return data_.size() - pos_; }
  [[nodiscard]] bool at_end() const { return pos_ >= data_.size(); }
  [[nodiscard]] std::int64_t line() const { return line_; }
  [[nodiscard]] std::span<const std::byte> data() const { return data_; }
  /// Reports the bytes consumed to `progress` as `base` + offset (nullptr: none).
  void track(Progress* progress, std::uint64_t base = 0) {
    progress_ = progress;
    progress_base_ = base;
  }
  /// Reports the current offset to the tracked progress (one comparison when nothing is due).
  void tick() {
    if (progress_) progress_->set(progress_base_ + pos_);
    if (pos_ >= release_at_) release_behind();
  }
  /// Drops the mapped pages of the file before the current position from memory
  /// (FileSource::release; tick() does it every kReleaseStep bytes): a reader never goes back
  /// to them, except through views it holds, which read the same bytes again if used.
  void release_behind() {
    if (!source_.file || pos_ <= released_) return;
    source_.release(data_.data() + released_, data_.data() + pos_);
    released_ = pos_;
    release_at_ = pos_ + kReleaseStep;
  }
  /// The place (offset and line) to come back to with `restore`.
  [[nodiscard]] std::pair<std::size_t, std::int64_t> mark() const { return {pos_, line_}; }
  void restore(std::pair<std::size_t, std::int64_t> m) {
    pos_ = m.first;
    line_ = m.second;
  }
  void seek(std::size_t offset) {
    if (offset > data_.size()) fail_at_byte(offset, "seek past end of file");
    pos_ = offset;
  }

  // ---- errors ----
  [[noreturn]] void fail_line(std::string_view what) const {
    if (report_offsets_) fail_at_byte(pos_, what);
    throw Error(at_line(name_, line_, what));
  }
  /// Makes `fail_line` (and so every text error) report the byte offset instead of the line.
  /// For formats that mix text with binary blocks (VTK legacy BINARY), where line numbers stop
  /// meaning anything after the first block. Off by default.
  void report_byte_offsets(bool on) { report_offsets_ = on; }
  [[noreturn]] void fail_byte(std::string_view what) const { fail_at_byte(pos_, what); }
  [[noreturn]] void fail_at_byte(std::size_t offset, std::string_view what) const {
    throw Error(at_byte(name_, offset, what));
  }

  // ---- text ----
  static bool is_space(char c) { return is_ascii_space(c); }
  [[nodiscard]] char peek_char() const {
    return at_end() ? '\0' : static_cast<char>(data_[pos_]);
  }

  /// Skips whitespace (counting lines).
  void skip_space() {
    while (pos_ < data_.size()) {
      char c = static_cast<char>(data_[pos_]);
      if (!is_space(c)) break;
      if (c == '\n') ++line_;
      ++pos_;
    }
  }

  /// Next whitespace-delimited token; empty at end of file.
  [[nodiscard]] std::string_view token() {
    skip_space();
    std::size_t start = pos_;
    while (pos_ < data_.size() && !is_space(static_cast<char>(data_[pos_]))) ++pos_;
    tick();
    return view(start, pos_);
  }
  /// Next token, failing with "expected <what>" at end of file.
  [[nodiscard]] std::string_view require_token(std::string_view what) {
    auto t = token();
    if (t.empty()) fail_line("unexpected end of file, expected " + std::string(what));
    return t;
  }
  /// Next token without consuming it.
  [[nodiscard]] std::string_view peek_token() {
    std::size_t p = pos_;
    std::int64_t l = line_;
    auto t = token();
    pos_ = p;
    line_ = l;
    return t;
  }

  /// Rest of the current line (without the newline, trailing '\r' removed); consumes the
  /// newline. Returns false at end of file.
  bool read_line(std::string_view& out) {
    if (at_end()) return false;
    std::size_t start = pos_;
    while (pos_ < data_.size() && static_cast<char>(data_[pos_]) != '\n') ++pos_;
    std::size_t end = pos_;
    if (pos_ < data_.size()) {
      ++pos_;
      ++line_;
    }
    if (end > start && static_cast<char>(data_[end - 1]) == '\r') --end;
    out = view(start, end);
    tick();
    return true;
  }
  /// Skips to just after the next newline (or to the end).
  void skip_line() {
    std::string_view ignored;
    read_line(ignored);
  }

  template <class T>
  [[nodiscard]] T parse_token(std::string_view what) {
    auto t = require_token(what);
    return parse<T>(t, what);
  }

  /// `count` tokens parsed as T into `out`: big arrays in parallel (parse_numbers); a file that
  /// ends early or holds a bad token is parsed again one token at a time, which reports it at
  /// its line as parse_token does.
  template <class T>
  void parse_tokens(std::size_t count, T* out, std::string_view what) {
    constexpr std::size_t kParallelFrom = std::size_t{1} << 16;
    if (count >= kParallelFrom) {
      const ParsedNumbers r = parse_numbers(view(pos_, data_.size()), count, out);
      if (r.found == count && !r.bad) {
        pos_ += r.end;
        line_ += r.lines;
        tick();
        return;
      }
    }
    for (std::size_t i = 0; i < count; ++i) out[i] = parse_token<T>(what);
  }

  template <class T>
  [[nodiscard]] T parse(std::string_view t, std::string_view what) const {
    T value{};
    if (parse_number(t, value)) return value;
    if constexpr (std::is_integral_v<T>) {
      const char* b = t.data() + (!t.empty() && t.front() == '+' ? 1 : 0);
      const auto [p, ec] = std::from_chars(b, t.data() + t.size(), value);
      if (ec == std::errc::result_out_of_range && p == t.data() + t.size()) {
        fail_line(std::string(what) + " " + quoted(t) + " is out of range");
      }
    }
    fail_line("expected " + std::string(what) + ", found " + quoted(t));
  }

  /// Parses a non-negative count and checks it against an upper bound derived from the bytes
  /// left (each item needs at least `min_bytes_each` bytes), so a lying header cannot make us
  /// allocate gigabytes.
  [[nodiscard]] std::size_t parse_count(std::string_view what, std::size_t min_bytes_each) {
    auto t = require_token(what);
    auto v = parse<std::int64_t>(t, what);
    if (v < 0) fail_line(std::string(what) + " " + std::to_string(v) + " is negative");
    check_count(static_cast<std::uint64_t>(v), min_bytes_each, what);
    return static_cast<std::size_t>(v);
  }
  void check_count(std::uint64_t n, std::size_t min_bytes_each, std::string_view what) const {
    if (min_bytes_each == 0) return;
    if (n > remaining() / min_bytes_each + 1) {
      fail_line(std::string(what) + " " + std::to_string(n) + " exceeds what the remaining " +
                std::to_string(remaining()) + " bytes of the file can hold");
    }
  }

  // ---- binary ----
  void require_bytes(std::size_t n, std::string_view what) const {
    if (n > remaining()) {
      fail_byte("truncated: " + std::string(what) + " needs " + std::to_string(n) +
                " bytes but only " + std::to_string(remaining()) + " remain");
    }
  }
  template <class T>
  [[nodiscard]] T read(Endian endian, std::string_view what) {
    require_bytes(sizeof(T), what);
    T v;
    std::memcpy(&v, data_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    if (endian != kHostEndian) v = byteswap_value(v);
    return v;
  }
  /// Reads `count` values of T into `out` (a std::vector or Buffer of T, resized), converting to
  /// host order.
  template <class Vec>
  void read_array(std::size_t count, Endian endian, Vec& out, std::string_view what) {
    using T = typename Vec::value_type;
    require_values(count, sizeof(T), what);
    out.resize(count);
    copy_elements(source_, data_.data() + pos_, reinterpret_cast<std::byte*>(out.data()), count,
                  sizeof(T), endian != kHostEndian, progress_, progress_base_ + pos_);
    pos_ += count * sizeof(T);
  }
  /// Hands the next `count` values of `size` bytes to `stream` in pieces (stream_bytes: the
  /// mapped pages stay untouched) and moves past them.
  void stream_values(std::size_t count, std::size_t size, TupleStream& stream,
                     std::string_view what) {
    require_values(count, size, what);
    io_detail::stream_bytes(source_, data_.data() + pos_, count * size, stream, progress_,
                            progress_base_ + pos_);
    pos_ += count * size;
    tick();
  }
  /// Fails unless `count` values of `size` bytes remain.
  void require_values(std::size_t count, std::size_t size, std::string_view what) const {
    if (count > remaining() / size) {
      fail_byte("truncated: " + std::string(what) + " needs " + std::to_string(count) +
                " values of " + std::to_string(size) + " bytes but only " +
                std::to_string(remaining()) + " bytes remain");
    }
  }
  /// Raw bytes, without conversion.
  [[nodiscard]] std::span<const std::byte> read_bytes(std::size_t n, std::string_view what) {
    require_bytes(n, what);
    auto s = data_.subspan(pos_, n);
    pos_ += n;
    tick();
    return s;
  }
  void skip(std::size_t n, std::string_view what) {
    require_bytes(n, what);
    pos_ += n;
    tick();
  }

 private:
  [[nodiscard]] std::string_view view(std::size_t b, std::size_t e) const {
    return {reinterpret_cast<const char*>(data_.data()) + b, e - b};
  }

  static constexpr std::size_t kReleaseStep = std::size_t{8} << 20;

  FileSource source_;
  std::size_t released_ = 0;                  // the pages before this are released
  std::size_t release_at_ = kReleaseStep;     // tick() releases when pos_ reaches this
  std::span<const std::byte> data_;
  std::string name_;
  std::size_t pos_ = 0;
  std::int64_t line_ = 1;
  bool report_offsets_ = false;
  Progress* progress_ = nullptr;
  std::uint64_t progress_base_ = 0;
};

/// The words of a line: the runs of characters between white space (Scanner::is_space).
inline std::vector<std::string_view> split_words(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && Scanner::is_space(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !Scanner::is_space(line[i])) ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
  return words;
}

/// Case-insensitive ASCII equality.
inline bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    char x = a[i], y = b[i];
    if (x >= 'A' && x <= 'Z') x = static_cast<char>(x - 'A' + 'a');
    if (y >= 'A' && y <= 'Z') y = static_cast<char>(y - 'A' + 'a');
    if (x != y) return false;
  }
  return true;
}

/// Multiplies with overflow check; returns false on overflow.
inline bool mul_overflow(std::uint64_t a, std::uint64_t b, std::uint64_t& out) {
  return __builtin_mul_overflow(a, b, &out);
}

}  // namespace isoforge::io_detail
