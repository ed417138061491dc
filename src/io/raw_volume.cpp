// Raw volume headers:
//  * NRRD ("Nearly Raw Raster Data", teem, NRRD0001–NRRD0005 file format specification,
//    https://teem.sourceforge.net/nrrd/format.html): `.nhdr` detached and `.nrrd` attached
//    headers, raw and gzip encodings, single data files, `data file: <format> <min> <max> <step>
//    [<subdim>]` and `data file: LIST [<subdim>]` lists, byte skip and line skip;
//  * MetaImage (ITK MetaIO, https://itk.org/Wiki/ITK/MetaIO/Documentation): `.mhd` + raw file
//    and `.mha` with LOCAL data, optional zlib compression, file patterns and lists.
// Both produce ImageData with one point array "Scalars" of the file's element type.

#include <zlib.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "detail/scanner.hpp"
#include "detail/summaries.hpp"
#include "detail/tuple_stream.hpp"
#include "isoforge/io/io.hpp"
#include "isoforge/io/raw_volume.hpp"

namespace isoforge {

namespace {

namespace fs = std::filesystem;
using io_detail::ascii_lower;
using io_detail::Endian;
using io_detail::iequals;
using io_detail::Scanner;
using io_detail::split_words;
using io_detail::trim_space;

// ---------------------------------------------------------------------------------------------
// Small text helpers


std::string clip(std::string_view s) { return io_detail::printable(s, 60); }

/// Error at a header line.
[[noreturn]] void fail_at(const std::string& file, std::int64_t line, const std::string& what) {
  throw Error(at_line(file, line, what));
}

std::optional<std::int64_t> to_int(std::string_view t) {
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  std::int64_t v = 0;
  auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (ec != std::errc() || p != t.data() + t.size()) return std::nullopt;
  return v;
}

std::optional<double> to_double(std::string_view t) {
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  double v = 0;
  auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (ec == std::errc::result_out_of_range) return std::nullopt;
  if (ec != std::errc() || p != t.data() + t.size()) return std::nullopt;
  return v;
}

std::int64_t int_value(std::string_view t, const std::string& file, std::int64_t line,
                       const std::string& what) {
  auto v = to_int(t);
  if (!v) fail_at(file, line, "expected an integer for " + what + ", found '" + clip(t) + "'");
  return *v;
}

std::vector<std::int64_t> int_list(std::string_view value, const std::string& file,
                                   std::int64_t line, const std::string& what) {
  std::vector<std::int64_t> out;
  for (auto w : split_words(value)) out.push_back(int_value(w, file, line, what));
  return out;
}

double double_value(std::string_view t, const std::string& file, std::int64_t line,
                    const std::string& what) {
  auto v = to_double(t);
  if (!v) fail_at(file, line, "expected a number for " + what + ", found '" + clip(t) + "'");
  return *v;
}

std::vector<double> double_list(std::string_view value, const std::string& file, std::int64_t line,
                                const std::string& what) {
  std::vector<double> out;
  for (auto w : split_words(value)) out.push_back(double_value(w, file, line, what));
  return out;
}

// ---------------------------------------------------------------------------------------------
// Data files

/// Data file names: an explicit list, or a pattern expanded on demand (so a header naming a
/// billion files fails at the first missing one instead of building a billion names).
struct FileList {
  std::vector<std::string> names;
  std::string pattern;
  std::int64_t first = 0, step = 1;
  std::size_t pattern_count = 0;
  std::string header;
  std::int64_t line = 0;

  [[nodiscard]] std::size_t size() const { return pattern.empty() ? names.size() : pattern_count; }
  [[nodiscard]] bool empty() const { return size() == 0; }
  [[nodiscard]] std::string name(std::size_t i) const;
};

/// Where the samples come from and how they are stored.
struct DataSpec {
  std::string header;  // header file name (for messages)
  fs::path base_dir;   // for relative data file names
  FileList files;      // empty: attached to the header
  io_detail::FileSource attached;  // the header file's bytes (and file)
  std::size_t attached_offset = 0;  // where the attached data starts in the header bytes
  std::int64_t byte_skip = 0;       // -1: data is at the end of the (decoded) file
  std::int64_t line_skip = 0;
  bool compressed = false;  // gzip (NRRD) or zlib (MetaImage) stream
  ScalarType type = ScalarType::UInt8;
  int components = 1;
  Endian endian = io_detail::kHostEndian;
  std::size_t tuples = 0;
  // Summaries: the samples go through this instead of into an array (io::summarize_file).
  io_detail::TupleStream* stream = nullptr;
  // Progress of loading the samples: fractions [progress_from, 1] of the callback (none if null).
  const ProgressCallback* progress = nullptr;
  double progress_from = 0;
};

fs::path resolve(const DataSpec& spec, const std::string& file) {
  fs::path p(file);
  if (p.is_relative() && !spec.base_dir.empty()) p = spec.base_dir / p;
  return p;
}

std::string data_label(const DataSpec& spec, const std::string& file) {
  return spec.header + ": data file '" + clip(file) + "'";
}

/// Size of a regular data file, or an Error naming header and data file.
std::uint64_t data_file_size(const DataSpec& spec, const std::string& file) {
  const fs::path p = resolve(spec, file);
  std::error_code ec;
  const auto st = fs::status(p, ec);
  if (ec || !fs::exists(st))
    throw Error(data_label(spec, file) + " (" + p.string() + ") does not exist");
  if (!fs::is_regular_file(st)) throw Error(data_label(spec, file) + " is not a regular file");
  const auto size = fs::file_size(p, ec);
  if (ec) throw Error(data_label(spec, file) + ": cannot determine its size: " + ec.message());
  return size;
}

/// Inflates a zlib or gzip stream into the `out_size` bytes at `out`, or with `stream` into the
/// stream (`out` unused), the first `skip` bytes dropped.
void inflate_into(std::span<const std::byte> in, std::byte* out, std::size_t out_size,
                  const std::string& label, io_detail::TupleStream* stream = nullptr,
                  std::size_t skip = 0) {
  // Deflate cannot expand data more than about 1032:1; a header asking for more lies.
  if (out_size / 1032 > in.size() + 64) {
    throw Error(label + ": " + std::to_string(in.size()) + " compressed bytes cannot hold the " +
                std::to_string(out_size) + " bytes the header describes");
  }
  z_stream z{};
  if (inflateInit2(&z, 15 + 32) != Z_OK) throw Error(label + ": cannot initialise zlib");
  std::size_t in_pos = 0, out_pos = 0;
  int rc = Z_OK;
  constexpr std::size_t kChunk = std::size_t{1} << 30;
  while (out_pos < out_size) {
    if (z.avail_in == 0 && in_pos < in.size()) {
      const std::size_t n = std::min(kChunk, in.size() - in_pos);
      z.next_in = reinterpret_cast<Bytef*>(const_cast<std::byte*>(in.data() + in_pos));
      z.avail_in = static_cast<uInt>(n);
      in_pos += n;
    }
    // Streamed: pieces into the stream's window, the first `skip` bytes dropped.
    const std::size_t n_out =
        std::min(stream ? io_detail::TupleStream::kPiece : kChunk, out_size - out_pos);
    std::byte* to = stream ? stream->window(n_out) : out + out_pos;
    z.next_out = reinterpret_cast<Bytef*>(to);
    z.avail_out = static_cast<uInt>(n_out);
    rc = inflate(&z, Z_NO_FLUSH);
    const std::size_t got = n_out - z.avail_out;
    if (stream) {
      const std::size_t drop = std::min(got, skip > out_pos ? skip - out_pos : 0);
      if (drop > 0) std::memmove(to, to + drop, got - drop);
      stream->filled(got - drop);
    }
    out_pos += got;
    if (rc == Z_STREAM_END) break;
    if (rc == Z_BUF_ERROR && z.avail_in == 0 && in_pos >= in.size()) break;  // input exhausted
    if (rc != Z_OK && rc != Z_BUF_ERROR) {
      const std::string msg = z.msg ? z.msg : "error " + std::to_string(rc);
      inflateEnd(&z);
      throw Error(label + ": corrupt compressed data (" + msg + ")");
    }
  }
  inflateEnd(&z);
  if (out_pos < out_size) {
    throw Error(label + ": truncated: compressed data decompresses to " + std::to_string(out_pos) +
                " bytes, the header needs " + std::to_string(out_size));
  }
}

/// Skips `lines` newline-terminated lines at the start of `bytes`; returns the new offset.
std::size_t skip_lines(std::span<const std::byte> bytes, std::size_t start, std::int64_t lines,
                       const std::string& label) {
  std::size_t pos = start;
  for (std::int64_t l = 0; l < lines; ++l) {
    while (pos < bytes.size() && bytes[pos] != std::byte{'\n'}) ++pos;
    if (pos >= bytes.size()) {
      throw Error(label + ": line skip " + std::to_string(lines) +
                  " runs past the end of the data");
    }
    ++pos;
  }
  return pos;
}

/// Decodes one file's bytes (starting at `start`) into `out`: raw data copied from the file
/// (io_detail::FileSource::copy, no pass over the mapping), compressed data inflated in place.
void decode_piece(const DataSpec& spec, const io_detail::FileSource& src, std::size_t start,
                  std::byte* out, std::size_t out_size, const std::string& label) {
  const std::span<const std::byte> bytes = src.bytes;
  std::size_t pos = skip_lines(bytes, start, spec.line_skip, label);
  const std::uint64_t avail = bytes.size() - pos;
  if (!spec.compressed) {
    if (spec.byte_skip == -1) {
      if (avail < out_size) {
        throw Error(label + ": truncated: needs " + std::to_string(out_size) + " bytes, has " +
                    std::to_string(avail));
      }
      pos = bytes.size() - out_size;
    } else {
      const auto skip = static_cast<std::uint64_t>(spec.byte_skip);
      if (skip > avail || avail - skip < out_size) {
        throw Error(label + ": truncated at byte " + std::to_string(bytes.size()) + ": needs " +
                    std::to_string(out_size) + " bytes of data after skipping " +
                    std::to_string(pos + skip) + ", has " +
                    std::to_string(skip > avail ? 0 : avail - skip));
      }
      pos += static_cast<std::size_t>(skip);
    }
    if (spec.stream) {
      io_detail::stream_bytes(src, bytes.data() + pos, out_size, *spec.stream);
    } else {
      src.copy(bytes.data() + pos, out, out_size);
    }
    return;
  }
  const auto skip = static_cast<std::uint64_t>(spec.byte_skip);  // -1 rejected for compressed
  std::uint64_t total = 0;
  if (__builtin_add_overflow(skip, static_cast<std::uint64_t>(out_size), &total) ||
      total / 1032 > avail + 64) {
    throw Error(label + ": " + std::to_string(avail) + " compressed bytes cannot hold the " +
                std::to_string(out_size) + " bytes (plus byte skip " + std::to_string(skip) +
                ") the header describes");
  }
  if (spec.stream) {
    // `out` has no storage here: the stream takes the bytes after the skip.
    inflate_into(bytes.subspan(pos), nullptr, static_cast<std::size_t>(total), label, spec.stream,
                 static_cast<std::size_t>(skip));
  } else if (skip == 0) {
    inflate_into(bytes.subspan(pos), out, out_size, label);
  } else {
    std::vector<std::byte> tmp(static_cast<std::size_t>(total));
    inflate_into(bytes.subspan(pos), tmp.data(), tmp.size(), label);
    if (out_size > 0) std::memcpy(out, tmp.data() + skip, out_size);
  }
}

/// Loads and converts all samples described by `spec`.
DataArray load_samples(const DataSpec& spec) {
  const std::size_t elem = scalar_size(spec.type) * static_cast<std::size_t>(spec.components);
  std::uint64_t total = 0;
  if (io_detail::mul_overflow(spec.tuples, elem, total) ||
      total > static_cast<std::uint64_t>(PTRDIFF_MAX)) {
    throw Error(spec.header + ": " + std::to_string(spec.tuples) + " samples of " +
                std::to_string(elem) + " bytes overflow the addressable size");
  }
  DataArray a;  // allocated once the data is known to be there, and decoded into
  // Where the bytes from `offset` go (nothing when streamed: only the sizes count).
  const auto samples = [&](std::uint64_t offset) {
    return spec.stream ? nullptr : a.bytes() + offset;
  };
  static const ProgressCallback kNone;
  const ProgressCallback& callback = spec.progress ? *spec.progress : kNone;
  io_detail::Progress progress;
  if (spec.files.empty()) {
    // Attached data: check that it can be there before allocating.
    const std::uint64_t avail = spec.attached.bytes.size() - spec.attached_offset;
    if (!spec.compressed) {
      const std::uint64_t skip =
          spec.byte_skip > 0 ? static_cast<std::uint64_t>(spec.byte_skip) : 0;
      if (skip > avail || avail - skip < total) {
        throw Error(at_byte(spec.header, spec.attached.bytes.size(),
                            "truncated: attached data needs " + std::to_string(total) +
                                " bytes after byte " + std::to_string(spec.attached_offset + skip) +
                                ", the file has " + std::to_string(spec.attached.bytes.size())));
      }
    } else if (total / 1032 > avail + 64) {
      throw Error(spec.header + ": attached data: " + std::to_string(avail) +
                  " compressed bytes cannot hold the " + std::to_string(total) +
                  " bytes the header describes");
    }
    if (!spec.stream) a = DataArray::uninitialized("Scalars", spec.type, spec.components, spec.tuples);
    progress = io_detail::Progress(callback, 2 * total, "reading", spec.progress_from);
    decode_piece(spec, spec.attached, spec.attached_offset, samples(0),
                 static_cast<std::size_t>(total), spec.header + ": attached data");
    progress.add(total);
  } else {
    const std::uint64_t nfiles = spec.files.size();
    if (total % nfiles != 0) {
      throw Error(spec.header + ": " + std::to_string(total) +
                  " bytes of data cannot be split evenly over " + std::to_string(nfiles) +
                  " data files");
    }
    const std::uint64_t per_file = total / nfiles;
    // Check every file before allocating anything.
    std::vector<std::uint64_t> sizes;
    for (std::size_t i = 0; i < spec.files.size(); ++i) {
      const std::string f = spec.files.name(i);
      const std::uint64_t size = data_file_size(spec, f);
      const std::uint64_t skip =
          spec.byte_skip > 0 ? static_cast<std::uint64_t>(spec.byte_skip) : 0;
      if (spec.compressed) {
        if (per_file / 1032 > size + 64) {
          throw Error(data_label(spec, f) + ": " + std::to_string(size) +
                      " compressed bytes cannot hold the " + std::to_string(per_file) +
                      " bytes the header describes");
        }
      } else if (size < skip || size - skip < per_file) {
        throw Error(data_label(spec, f) + ": too short: " + std::to_string(size) +
                    " bytes, needs " + std::to_string(per_file) + " bytes of data after skipping " +
                    std::to_string(skip));
      }
      sizes.push_back(size);
    }
    if (!spec.stream) a = DataArray::uninitialized("Scalars", spec.type, spec.components, spec.tuples);
    // Work: each file's piece decoded into its place, then the samples' byte order.
    progress = io_detail::Progress(callback, 2 * total, "reading", spec.progress_from);
    for (std::size_t i = 0; i < spec.files.size(); ++i) {
      const std::string f = spec.files.name(i);
      const io_detail::MappedFile file(resolve(spec, f));
      if (file.bytes().size() != sizes[i]) {
        throw Error(data_label(spec, f) + ": changed size while being read");
      }
      decode_piece(spec, io_detail::FileSource(file), 0, samples(i * per_file),
                   static_cast<std::size_t>(per_file), data_label(spec, f));
      progress.add(per_file);
    }
  }
  const std::size_t elem_size = scalar_size(spec.type);
  constexpr std::size_t kBlock = std::size_t{4} << 20;  // a multiple of every element size
  for (std::size_t at = 0; at < static_cast<std::size_t>(total); at += kBlock) {
    const std::size_t n = std::min(kBlock, static_cast<std::size_t>(total) - at);
    if (spec.endian != io_detail::kHostEndian && !spec.stream) {
      io_detail::swap_elements(a.bytes() + at, n / elem_size, elem_size);
    }
    progress.add(n);
  }
  progress.finish();
  return a;
}

/// Expands a printf-style pattern with exactly one %d / %i / %u conversion (flags 0, -, +,
/// space and a width allowed; %% is a literal percent sign).
std::string expand_pattern(std::string_view pattern, std::int64_t value, const std::string& file,
                           std::int64_t line) {
  std::string out;
  int conversions = 0;
  for (std::size_t i = 0; i < pattern.size(); ++i) {
    const char c = pattern[i];
    if (c != '%') {
      out += c;
      continue;
    }
    if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
      out += '%';
      ++i;
      continue;
    }
    std::size_t j = i + 1;
    bool zero = false, left = false, plus = false, space = false;
    while (j < pattern.size() &&
           std::string_view("0-+ ").find(pattern[j]) != std::string_view::npos) {
      zero = zero || pattern[j] == '0';
      left = left || pattern[j] == '-';
      plus = plus || pattern[j] == '+';
      space = space || pattern[j] == ' ';
      ++j;
    }
    std::size_t width = 0;
    while (j < pattern.size() && pattern[j] >= '0' && pattern[j] <= '9' && width < 1000) {
      width = width * 10 + static_cast<std::size_t>(pattern[j] - '0');
      ++j;
    }
    if (j >= pattern.size() || (pattern[j] != 'd' && pattern[j] != 'i' && pattern[j] != 'u')) {
      fail_at(file, line,
              "data file pattern '" + clip(pattern) +
                  "' has an unsupported conversion (only %d, %i, %u with flags and width)");
    }
    if (width > 64)
      fail_at(file, line, "data file pattern '" + clip(pattern) + "' has a width over 64");
    if (++conversions > 1) {
      fail_at(file, line, "data file pattern '" + clip(pattern) + "' has more than one conversion");
    }
    const std::uint64_t magnitude =
        value < 0 ? 0 - static_cast<std::uint64_t>(value) : static_cast<std::uint64_t>(value);
    const std::string digits = std::to_string(magnitude);
    const std::string sign = value < 0 ? "-" : plus ? "+" : space ? " " : "";
    std::string num;
    if (zero && !left && sign.size() + digits.size() < width) {
      num = sign + std::string(width - sign.size() - digits.size(), '0') + digits;
    } else {
      num = sign + digits;
      if (num.size() < width) {
        num = left ? num + std::string(width - num.size(), ' ')
                   : std::string(width - num.size(), ' ') + num;
      }
    }
    out += num;
    i = j;
  }
  if (conversions == 0) {
    fail_at(file, line, "data file pattern '" + clip(pattern) + "' has no %d conversion");
  }
  return out;
}

std::string FileList::name(std::size_t i) const {
  if (pattern.empty()) return names[i];
  return expand_pattern(pattern, first + static_cast<std::int64_t>(i) * step, header, line);
}

/// Files of a `<pattern> <min> <max> <step>` list; there must be exactly `need` of them.
FileList pattern_files(const std::vector<std::string_view>& w, const std::string& file,
                       std::int64_t line, std::uint64_t need) {
  const std::int64_t first = int_value(w[1], file, line, "the first file number");
  const std::int64_t last = int_value(w[2], file, line, "the last file number");
  const std::int64_t step = int_value(w[3], file, line, "the file number step");
  if (step == 0) fail_at(file, line, "data file step is 0");
  std::int64_t span = 0;
  if (__builtin_sub_overflow(last, first, &span) || (span != 0 && (span < 0) != (step < 0))) {
    fail_at(file, line,
            "data file range " + std::to_string(first) + " .. " + std::to_string(last) +
                " cannot be reached with step " + std::to_string(step));
  }
  const std::uint64_t n = static_cast<std::uint64_t>(span / step) + 1;
  if (n != need) {
    fail_at(file, line,
            "data file list names " + std::to_string(n) + " files, the sizes need " +
                std::to_string(need));
  }
  FileList list;
  list.pattern = std::string(w[0]);
  list.first = first;
  list.step = step;
  list.pattern_count = static_cast<std::size_t>(n);
  list.header = file;
  list.line = line;
  (void)list.name(0);  // validates the pattern
  return list;
}

/// Number of files a list with `subdim` (dimension of the data in each file) must name.
std::uint64_t files_for_subdim(const std::vector<std::int64_t>& sizes, std::int64_t subdim,
                               const std::string& file, std::int64_t line) {
  const auto dim = static_cast<std::int64_t>(sizes.size());
  if (subdim < 0 || subdim > dim) {
    fail_at(file, line,
            "data file subdimension " + std::to_string(subdim) + " is not in 0.." +
                std::to_string(dim));
  }
  std::uint64_t n = 1;
  for (std::int64_t a = subdim; a < dim; ++a)
    n *= static_cast<std::uint64_t>(sizes[static_cast<std::size_t>(a)]);
  return n;
}

/// The image with its samples (`summary` null), or the summary of the image with its samples
/// streamed through it.
ImageData finish_volume(ImageData img, DataSpec& spec, const std::string& file,
                        DatasetSummary* summary) {
  if (summary) {
    ValueRanges ranges(spec.components);
    io_detail::TupleStream stream(spec.type, spec.components,
                                  spec.endian != io_detail::kHostEndian,
                                  [&](const std::byte* v, std::size_t n) {
                                    ranges.add(spec.type, v, n);
                                  });
    spec.stream = &stream;
    (void)load_samples(spec);
    *summary = isoforge::summarize(img);
    summary->streamed = true;
    summary->point_data.arrays.push_back(
        {"Scalars", spec.type, spec.components, spec.tuples, std::move(ranges)});
    summary->point_data.active[static_cast<std::size_t>(AttributeRole::Scalars)] = "Scalars";
    return img;
  }
  img.point_data.add(load_samples(spec), AttributeRole::Scalars);
  try {
    img.validate();
  } catch (const Error& e) {
    throw Error(file + ": " + e.what());
  }
  return img;
}

Dims dims_from(const std::vector<std::int64_t>& sizes, const std::string& file, std::int64_t line) {
  Dims dims{1, 1, 1};
  for (std::size_t a = 0; a < sizes.size() && a < 3; ++a) {
    if (sizes[a] < 1) {
      fail_at(
          file, line,
          "size " + std::to_string(sizes[a]) + " of axis " + std::to_string(a) + " must be >= 1");
    }
    dims[a] = sizes[a];
  }
  try {
    (void)checked_point_count(dims, "sizes");
  } catch (const Error& e) {
    fail_at(file, line, e.what());
  }
  return dims;
}

// ---------------------------------------------------------------------------------------------
// NRRD

std::optional<ScalarType> nrrd_type(std::string_view t) {
  struct Name {
    const char* name;
    ScalarType type;
  };
  static const Name names[] = {{"signed char", ScalarType::Int8},
                               {"int8", ScalarType::Int8},
                               {"int8_t", ScalarType::Int8},
                               {"uchar", ScalarType::UInt8},
                               {"unsigned char", ScalarType::UInt8},
                               {"uint8", ScalarType::UInt8},
                               {"uint8_t", ScalarType::UInt8},
                               {"short", ScalarType::Int16},
                               {"short int", ScalarType::Int16},
                               {"signed short", ScalarType::Int16},
                               {"signed short int", ScalarType::Int16},
                               {"int16", ScalarType::Int16},
                               {"int16_t", ScalarType::Int16},
                               {"ushort", ScalarType::UInt16},
                               {"unsigned short", ScalarType::UInt16},
                               {"unsigned short int", ScalarType::UInt16},
                               {"uint16", ScalarType::UInt16},
                               {"uint16_t", ScalarType::UInt16},
                               {"int", ScalarType::Int32},
                               {"signed int", ScalarType::Int32},
                               {"int32", ScalarType::Int32},
                               {"int32_t", ScalarType::Int32},
                               {"uint", ScalarType::UInt32},
                               {"unsigned int", ScalarType::UInt32},
                               {"uint32", ScalarType::UInt32},
                               {"uint32_t", ScalarType::UInt32},
                               {"longlong", ScalarType::Int64},
                               {"long long", ScalarType::Int64},
                               {"long long int", ScalarType::Int64},
                               {"signed long long", ScalarType::Int64},
                               {"signed long long int", ScalarType::Int64},
                               {"int64", ScalarType::Int64},
                               {"int64_t", ScalarType::Int64},
                               {"ulonglong", ScalarType::UInt64},
                               {"unsigned long long", ScalarType::UInt64},
                               {"unsigned long long int", ScalarType::UInt64},
                               {"uint64", ScalarType::UInt64},
                               {"uint64_t", ScalarType::UInt64},
                               {"float", ScalarType::Float32},
                               {"double", ScalarType::Float64}};
  const std::string s = ascii_lower(trim_space(t));
  for (const Name& n : names) {
    if (s == n.name) return n.type;
  }
  return std::nullopt;
}

/// Parses "(a,b,c) (d,e,f) none ..." into vectors (empty for "none").
std::vector<std::vector<double>> nrrd_vectors(std::string_view value, const std::string& file,
                                              std::int64_t line, const std::string& what) {
  std::vector<std::vector<double>> out;
  std::size_t i = 0;
  while (i < value.size()) {
    if (Scanner::is_space(value[i])) {
      ++i;
      continue;
    }
    if (value.substr(i).starts_with("none")) {
      out.emplace_back();
      i += 4;
      continue;
    }
    if (value[i] != '(')
      fail_at(file, line, what + ": expected '(' or 'none' in '" + clip(value) + "'");
    const std::size_t close = value.find(')', i);
    if (close == std::string_view::npos)
      fail_at(file, line, what + ": missing ')' in '" + clip(value) + "'");
    std::vector<double> v;
    std::string_view inner = value.substr(i + 1, close - i - 1);
    while (true) {
      const std::size_t comma = inner.find(',');
      v.push_back(double_value(trim_space(inner.substr(0, comma)), file, line, what));
      if (comma == std::string_view::npos) break;
      inner.remove_prefix(comma + 1);
    }
    out.push_back(std::move(v));
    i = close + 1;
  }
  return out;
}

bool nrrd_known_ignored(const std::string& f) {
  static const char* const names[] = {
      "content",        "min",        "max",        "old min",           "oldmin",
      "old max",        "oldmax",     "units",      "space units",       "labels",
      "kinds",          "centerings", "centers",    "thicknesses",       "axis mins",
      "axismins",       "axis maxs",  "axismaxs",   "measurement frame", "sample units",
      "sampleunits",    "number",     "block size", "blocksize",         "space",
      "space dimension"};
  return std::any_of(std::begin(names), std::end(names), [&](const char* n) { return f == n; });
}

ImageData read_nrrd_impl(const io_detail::FileSource& data, const std::string& name,
                         const fs::path& base_dir,
                         const ProgressCallback* progress = nullptr, double progress_from = 0,
                         DatasetSummary* summary = nullptr) {
  Scanner sc(data, name);
  std::string_view line;
  if (!sc.read_line(line)) fail_at(name, 1, "empty file, expected the NRRD magic 'NRRD000X'");
  if (line.size() != 8 || !line.starts_with("NRRD000") || line[7] < '1' || line[7] > '9') {
    fail_at(name, 1, "bad magic: expected 'NRRD0001'..'NRRD0005', found '" + clip(line) + "'");
  }
  struct Field {
    std::string value;
    std::int64_t line = 0;
  };
  std::vector<std::pair<std::string, Field>> fields;
  std::vector<std::string> list_files;
  std::int64_t list_line = 0;
  bool in_list = false;
  bool blank_seen = false;
  while (true) {
    const std::int64_t ln = sc.line();
    if (!sc.read_line(line)) break;
    if (line.empty()) {
      blank_seen = true;
      break;
    }
    if (in_list) {
      const auto w = trim_space(line);
      if (!w.empty()) list_files.emplace_back(w);
      continue;
    }
    if (line.front() == '#') continue;
    if (line.find(":=") != std::string_view::npos) continue;  // key/value pair
    const std::size_t colon = line.find(": ");
    if (colon == std::string_view::npos) {
      fail_at(name, ln, "expected 'field: value', found '" + clip(line) + "'");
    }
    const std::string key = ascii_lower(line.substr(0, colon));
    const std::string value(trim_space(line.substr(colon + 2)));
    for (const auto& [k, f] : fields) {
      if (k == key ||
          ((k == "data file" || k == "datafile") && (key == "data file" || key == "datafile"))) {
        fail_at(name, ln,
                "duplicate field '" + clip(key) + "' (first on line " + std::to_string(f.line) + ")");
      }
    }
    static const char* const known[] = {
        "type",         "dimension", "sizes",     "spacings",  "space directions",
        "space origin", "endian",    "encoding",  "data file", "datafile",
        "byte skip",    "byteskip",  "line skip", "lineskip"};
    if (std::none_of(std::begin(known), std::end(known), [&](const char* n) { return key == n; }) &&
        !nrrd_known_ignored(key)) {
      fail_at(name, ln, "unknown field '" + clip(key) + "'");
    }
    if ((key == "data file" || key == "datafile")) {
      const auto w = split_words(value);
      if (!w.empty() && w[0] == "LIST") {
        in_list = true;
        list_line = ln;
      }
    }
    fields.emplace_back(key, Field{value, ln});
  }
  auto get = [&](std::initializer_list<const char*> keys) -> const Field* {
    for (const auto& [k, f] : fields) {
      for (const char* key : keys) {
        if (k == key) return &f;
      }
    }
    return nullptr;
  };
  auto require = [&](const char* key) -> const Field& {
    const Field* f = get({key});
    if (!f) fail_at(name, 0, "missing required field '" + std::string(key) + "'");
    return *f;
  };

  // ---- type, dimension, sizes ----
  const Field& type_f = require("type");
  const auto type = nrrd_type(type_f.value);
  if (!type) {
    if (iequals(type_f.value, "block")) fail_at(name, type_f.line, "type 'block' is not supported");
    fail_at(name, type_f.line, "unknown type '" + clip(type_f.value) + "'");
  }
  const Field& dim_f = require("dimension");
  const std::int64_t dim = int_value(trim_space(dim_f.value), name, dim_f.line, "dimension");
  if (dim < 1 || dim > 3) {
    fail_at(name, dim_f.line, "dimension " + std::to_string(dim) + " is not supported (1, 2 or 3)");
  }
  const Field& sizes_f = require("sizes");
  const auto sizes = int_list(sizes_f.value, name, sizes_f.line, "sizes");
  if (static_cast<std::int64_t>(sizes.size()) != dim) {
    fail_at(name, sizes_f.line,
            "sizes has " + std::to_string(sizes.size()) + " values, dimension is " +
                std::to_string(dim));
  }
  ImageData img;
  img.dims = dims_from(sizes, name, sizes_f.line);

  // ---- geometry ----
  const Field* spacings_f = get({"spacings"});
  const Field* dirs_f = get({"space directions"});
  if (spacings_f && dirs_f) {
    fail_at(name, dirs_f->line, "both 'spacings' and 'space directions' are given");
  }
  if (spacings_f) {
    const auto sp = double_list(spacings_f->value, name, spacings_f->line, "spacings");
    if (static_cast<std::int64_t>(sp.size()) != dim) {
      fail_at(name, spacings_f->line,
              "spacings has " + std::to_string(sp.size()) + " values, dimension is " +
                  std::to_string(dim));
    }
    for (std::size_t a = 0; a < sp.size(); ++a) {
      if (std::isnan(sp[a])) continue;  // non-spatial axis
      if (!std::isfinite(sp[a]) || sp[a] == 0.0) {
        fail_at(name, spacings_f->line,
                "spacing " + std::to_string(sp[a]) + " of axis " + std::to_string(a) +
                    " must be finite and non-zero");
      }
      img.spacing[static_cast<int>(a)] = sp[a];
    }
  }
  if (dirs_f) {
    const auto dirs = nrrd_vectors(dirs_f->value, name, dirs_f->line, "space directions");
    if (static_cast<std::int64_t>(dirs.size()) != dim) {
      fail_at(name, dirs_f->line,
              "space directions has " + std::to_string(dirs.size()) + " entries, dimension is " +
                  std::to_string(dim));
    }
    for (std::size_t a = 0; a < dirs.size(); ++a) {
      const auto& v = dirs[a];
      if (v.empty()) continue;  // "none": non-spatial axis
      if (v.size() > 3 || a >= v.size()) {
        fail_at(name, dirs_f->line,
                "space direction of axis " + std::to_string(a) + " has " +
                    std::to_string(v.size()) + " components");
      }
      for (std::size_t c = 0; c < v.size(); ++c) {
        if (!std::isfinite(v[c]))
          fail_at(name, dirs_f->line, "space directions contain a non-finite value");
        if (c != a && v[c] != 0.0) {
          fail_at(name, dirs_f->line,
                  "space directions are not axis-aligned (non-diagonal); "
                  "only diagonal directions are supported");
        }
      }
      if (v[a] == 0.0)
        fail_at(name, dirs_f->line, "space direction of axis " + std::to_string(a) + " is zero");
      img.spacing[static_cast<int>(a)] = v[a];
    }
  }
  if (const Field* o = get({"space origin"})) {
    const auto v = nrrd_vectors(o->value, name, o->line, "space origin");
    if (v.size() != 1 || v[0].empty() || v[0].size() > 3) {
      fail_at(name, o->line, "space origin must be one vector like (x,y,z)");
    }
    for (std::size_t c = 0; c < v[0].size(); ++c) {
      if (!std::isfinite(v[0][c])) fail_at(name, o->line, "space origin is not finite");
      img.origin[static_cast<int>(c)] = v[0][c];
    }
  }

  // ---- storage ----
  DataSpec spec;
  spec.progress = progress;
  spec.progress_from = progress_from;
  spec.header = name;
  spec.base_dir = base_dir;
  spec.type = *type;
  spec.tuples = checked_point_count(img.dims, name);
  const Field& enc_f = require("encoding");
  const std::string enc = ascii_lower(trim_space(enc_f.value));
  if (enc == "gzip" || enc == "gz") {
    spec.compressed = true;
  } else if (enc != "raw") {
    fail_at(name, enc_f.line, "encoding " + clip(enc) + " not supported (raw and gzip are)");
  }
  if (const Field* e = get({"endian"})) {
    const std::string v = ascii_lower(trim_space(e->value));
    if (v == "little") {
      spec.endian = Endian::Little;
    } else if (v == "big") {
      spec.endian = Endian::Big;
    } else {
      fail_at(name, e->line, "endian must be 'little' or 'big', not '" + clip(v) + "'");
    }
  } else if (scalar_size(spec.type) > 1) {
    fail_at(name, 0,
            "missing field 'endian' (needed for multi-byte type " +
                std::string(scalar_type_name(spec.type)) + ")");
  }
  if (const Field* f = get({"byte skip", "byteskip"})) {
    spec.byte_skip = int_value(trim_space(f->value), name, f->line, "byte skip");
    if (spec.byte_skip < -1)
      fail_at(name, f->line, "byte skip " + std::to_string(spec.byte_skip) + " is negative");
    if (spec.byte_skip == -1 && spec.compressed) {
      fail_at(name, f->line, "byte skip -1 is only allowed with raw encoding");
    }
  }
  if (const Field* f = get({"line skip", "lineskip"})) {
    spec.line_skip = int_value(trim_space(f->value), name, f->line, "line skip");
    if (spec.line_skip < 0)
      fail_at(name, f->line, "line skip " + std::to_string(spec.line_skip) + " is negative");
  }
  if (const Field* f = get({"data file", "datafile"})) {
    const auto w = split_words(f->value);
    if (w.empty()) fail_at(name, f->line, "data file is empty");
    if (w[0] == "LIST") {
      const std::int64_t subdim =
          w.size() > 1 ? int_value(w[1], name, f->line, "subdimension") : dim - 1;
      if (w.size() > 2) fail_at(name, f->line, "unexpected text after 'LIST <subdim>'");
      const auto need = files_for_subdim(sizes, subdim, name, f->line);
      if (list_files.size() != need) {
        fail_at(name, list_line,
                "data file LIST names " + std::to_string(list_files.size()) +
                    " files, the sizes need " + std::to_string(need));
      }
      spec.files.names = std::move(list_files);
    } else if (w[0].find('%') != std::string_view::npos && (w.size() == 4 || w.size() == 5)) {
      const std::int64_t subdim =
          w.size() == 5 ? int_value(w[4], name, f->line, "subdimension") : dim - 1;
      spec.files = pattern_files(w, name, f->line, files_for_subdim(sizes, subdim, name, f->line));
    } else {
      spec.files.names = {f->value};
    }
  } else {
    if (!blank_seen) {
      fail_at(name, sc.line(),
              "no 'data file' field and no attached data (the header must end with "
              "an empty line before the data)");
    }
    spec.attached = data;
    spec.attached_offset = sc.offset();
  }
  return finish_volume(std::move(img), spec, name, summary);
}

// ---------------------------------------------------------------------------------------------
// MetaImage

std::optional<ScalarType> met_type(std::string_view t) {
  if (t == "MET_CHAR") return ScalarType::Int8;
  if (t == "MET_UCHAR") return ScalarType::UInt8;
  if (t == "MET_SHORT") return ScalarType::Int16;
  if (t == "MET_USHORT") return ScalarType::UInt16;
  if (t == "MET_INT" || t == "MET_LONG") return ScalarType::Int32;
  if (t == "MET_UINT" || t == "MET_ULONG") return ScalarType::UInt32;
  if (t == "MET_LONG_LONG") return ScalarType::Int64;
  if (t == "MET_ULONG_LONG") return ScalarType::UInt64;
  if (t == "MET_FLOAT") return ScalarType::Float32;
  if (t == "MET_DOUBLE") return ScalarType::Float64;
  return std::nullopt;
}

std::optional<bool> met_bool(std::string_view v) {
  if (iequals(v, "true") || v == "1") return true;
  if (iequals(v, "false") || v == "0") return false;
  return std::nullopt;
}

ImageData read_metaimage_impl(const io_detail::FileSource& data, const std::string& name,
                              const fs::path& base_dir,
                              const ProgressCallback* progress = nullptr, double progress_from = 0,
                         DatasetSummary* summary = nullptr) {
  Scanner sc(data, name);
  struct Field {
    std::string value;
    std::int64_t line = 0;
  };
  std::vector<std::pair<std::string, Field>> fields;
  std::vector<std::string> list_files;
  bool have_data_file = false;
  std::string_view line;
  while (!have_data_file) {
    const std::int64_t ln = sc.line();
    if (!sc.read_line(line)) break;
    if (trim_space(line).empty()) continue;
    const std::size_t eq = line.find('=');
    if (eq == std::string_view::npos) {
      if (ln == 1) fail_at(name, ln, "bad magic: not a MetaImage header (expected 'Key = Value')");
      fail_at(name, ln, "expected 'Key = Value', found '" + clip(line) + "'");
    }
    const std::string key = ascii_lower(trim_space(line.substr(0, eq)));
    const std::string value(trim_space(line.substr(eq + 1)));
    static const char* const known[] = {"objecttype",
                                        "objectsubtype",
                                        "ndims",
                                        "dimsize",
                                        "elementspacing",
                                        "elementsize",
                                        "offset",
                                        "origin",
                                        "position",
                                        "elementtype",
                                        "elementbyteordermsb",
                                        "binarydatabyteordermsb",
                                        "byteordermsb",
                                        "elementnumberofchannels",
                                        "headersize",
                                        "compresseddata",
                                        "compresseddatasize",
                                        "binarydata",
                                        "elementdatafile",
                                        "transformmatrix",
                                        "rotation",
                                        "orientation",
                                        "centerofrotation",
                                        "anatomicalorientation",
                                        "comment",
                                        "transformtype",
                                        "name",
                                        "id",
                                        "parentid",
                                        "color",
                                        "elementmin",
                                        "elementmax",
                                        "distanceunits",
                                        "acquisitiondate",
                                        "modality",
                                        "sequenceid",
                                        "elementsizevalid",
                                        "formattypename"};
    if (std::none_of(std::begin(known), std::end(known), [&](const char* n) { return key == n; })) {
      if (ln == 1 && fields.empty()) {
        fail_at(name, ln,
                "bad magic: unknown first key '" + clip(key) + "' (not a MetaImage header)");
      }
      fail_at(name, ln, "unknown key '" + clip(key) + "'");
    }
    for (const auto& [k, f] : fields) {
      if (k == key)
        fail_at(name, ln,
                "duplicate key '" + clip(key) + "' (first on line " + std::to_string(f.line) + ")");
    }
    fields.emplace_back(key, Field{value, ln});
    if (key == "elementdatafile") {
      have_data_file = true;
      const auto w = split_words(value);
      if (!w.empty() && iequals(w[0], "LIST")) {
        while (sc.read_line(line)) {
          const auto f = trim_space(line);
          if (!f.empty()) list_files.emplace_back(f);
        }
      }
    }
  }
  auto get = [&](std::initializer_list<const char*> keys) -> const Field* {
    for (const char* key : keys) {
      for (const auto& [k, f] : fields) {
        if (k == key) return &f;
      }
    }
    return nullptr;
  };
  auto require = [&](const char* key, const char* display) -> const Field& {
    const Field* f = get({key});
    if (!f) fail_at(name, 0, std::string("missing required key '") + display + "'");
    return *f;
  };

  if (const Field* f = get({"objecttype"}); f && !iequals(f->value, "Image")) {
    fail_at(name, f->line, "ObjectType '" + clip(f->value) + "' is not supported (Image is)");
  }
  const Field& nd_f = require("ndims", "NDims");
  const std::int64_t nd = int_value(nd_f.value, name, nd_f.line, "NDims");
  if (nd < 1 || nd > 3)
    fail_at(name, nd_f.line, "NDims " + std::to_string(nd) + " is not supported (1, 2 or 3)");
  const Field& ds_f = require("dimsize", "DimSize");
  const auto sizes = int_list(ds_f.value, name, ds_f.line, "DimSize");
  if (static_cast<std::int64_t>(sizes.size()) != nd) {
    fail_at(
        name, ds_f.line,
        "DimSize has " + std::to_string(sizes.size()) + " values, NDims is " + std::to_string(nd));
  }
  ImageData img;
  img.dims = dims_from(sizes, name, ds_f.line);
  auto vec3 = [&](const Field& f, const char* what, Vec3& out, bool nonzero) {
    const auto v = double_list(f.value, name, f.line, what);
    if (static_cast<std::int64_t>(v.size()) != nd) {
      fail_at(name, f.line,
              std::string(what) + " has " + std::to_string(v.size()) + " values, NDims is " +
                  std::to_string(nd));
    }
    for (std::size_t a = 0; a < v.size(); ++a) {
      if (!std::isfinite(v[a]) || (nonzero && v[a] == 0.0)) {
        fail_at(name, f.line,
                std::string(what) + " value " + std::to_string(v[a]) + " of axis " +
                    std::to_string(a) +
                    (nonzero ? " must be finite and non-zero" : " is not finite"));
      }
      out[static_cast<int>(a)] = v[a];
    }
  };
  if (const Field* f = get({"elementspacing", "elementsize"}))
    vec3(*f, "ElementSpacing", img.spacing, true);
  if (const Field* f = get({"offset", "origin", "position"})) vec3(*f, "Offset", img.origin, false);
  if (const Field* f = get({"transformmatrix", "rotation", "orientation"})) {
    const auto m = double_list(f->value, name, f->line, "TransformMatrix");
    if (static_cast<std::int64_t>(m.size()) != nd * nd) {
      fail_at(name, f->line,
              "TransformMatrix has " + std::to_string(m.size()) + " values, expected " +
                  std::to_string(nd * nd));
    }
    for (std::int64_t r = 0; r < nd; ++r) {
      for (std::int64_t c = 0; c < nd; ++c) {
        if (m[static_cast<std::size_t>(r * nd + c)] != (r == c ? 1.0 : 0.0)) {
          fail_at(name, f->line,
                  "TransformMatrix is not the identity; only axis-aligned images are supported");
        }
      }
    }
  }

  DataSpec spec;
  spec.progress = progress;
  spec.progress_from = progress_from;
  spec.header = name;
  spec.base_dir = base_dir;
  const Field& et_f = require("elementtype", "ElementType");
  const auto type = met_type(et_f.value);
  if (!type) fail_at(name, et_f.line, "unknown ElementType '" + clip(et_f.value) + "'");
  spec.type = *type;
  if (const Field* f = get({"elementnumberofchannels"})) {
    const std::int64_t c = int_value(f->value, name, f->line, "ElementNumberOfChannels");
    if (c < 1 || c > 4096) {
      fail_at(name, f->line, "ElementNumberOfChannels " + std::to_string(c) + " is not in 1..4096");
    }
    spec.components = static_cast<int>(c);
  }
  spec.endian = Endian::Little;
  if (const Field* f = get({"elementbyteordermsb", "binarydatabyteordermsb", "byteordermsb"})) {
    const auto b = met_bool(f->value);
    if (!b)
      fail_at(name, f->line, "byte order must be True or False, not '" + clip(f->value) + "'");
    spec.endian = *b ? Endian::Big : Endian::Little;
  }
  if (const Field* f = get({"binarydata"})) {
    const auto b = met_bool(f->value);
    if (!b)
      fail_at(name, f->line, "BinaryData must be True or False, not '" + clip(f->value) + "'");
    if (!*b) fail_at(name, f->line, "ASCII MetaImage data (BinaryData = False) is not supported");
  }
  if (const Field* f = get({"compresseddata"})) {
    const auto b = met_bool(f->value);
    if (!b)
      fail_at(name, f->line, "CompressedData must be True or False, not '" + clip(f->value) + "'");
    spec.compressed = *b;
  }
  if (const Field* f = get({"headersize"})) {
    spec.byte_skip = int_value(f->value, name, f->line, "HeaderSize");
    if (spec.byte_skip < -1)
      fail_at(name, f->line, "HeaderSize " + std::to_string(spec.byte_skip) + " is negative");
    if (spec.byte_skip == -1 && spec.compressed) {
      fail_at(name, f->line, "HeaderSize -1 cannot be used with compressed data");
    }
  }
  spec.tuples = checked_point_count(img.dims, name);

  const Field& df = require("elementdatafile", "ElementDataFile");
  const auto w = split_words(df.value);
  if (w.empty()) fail_at(name, df.line, "ElementDataFile is empty");
  if (iequals(w[0], "LOCAL")) {
    spec.attached = data;
    spec.attached_offset = sc.offset();
  } else if (iequals(w[0], "LIST")) {
    // MetaIO writes the files' dimension as "LIST 2D" (and reads it with atof): the D is dropped.
    std::string_view sub = w.size() > 1 ? w[1] : std::string_view{};
    if (sub.size() > 1 && (sub.back() == 'D' || sub.back() == 'd')) sub.remove_suffix(1);
    const std::int64_t subdim =
        w.size() > 1 ? int_value(sub, name, df.line, "subdimension") : nd - 1;
    const auto need = files_for_subdim(sizes, subdim, name, df.line);
    if (list_files.size() != need) {
      fail_at(name, df.line,
              "ElementDataFile LIST names " + std::to_string(list_files.size()) +
                  " files, the sizes need " + std::to_string(need));
    }
    spec.files.names = std::move(list_files);
  } else if (w[0].find('%') != std::string_view::npos && (w.size() == 4 || w.size() == 5)) {
    const std::int64_t subdim =
        w.size() == 5 ? int_value(w[4], name, df.line, "subdimension") : nd - 1;
    spec.files = pattern_files(w, name, df.line, files_for_subdim(sizes, subdim, name, df.line));
  } else {
    spec.files.names = {df.value};
  }
  return finish_volume(std::move(img), spec, name, summary);
}

}  // namespace

ImageData read_nrrd(std::span<const std::byte> data, std::string_view name,
                    const std::filesystem::path& base_dir) {
  return read_nrrd_impl(data, std::string(name), base_dir);
}

namespace {

// Loads a header file with progress, then its samples: the header is a weight-free first step
// when small (detached data), the first half of the work when big (attached data).
template <class Impl>
ImageData read_raw_volume(const std::filesystem::path& path, const ProgressCallback& callback,
                          Impl&& impl, DatasetSummary* summary = nullptr) {
  const std::uint64_t size = io_detail::file_size_or_zero(path);
  const double header_share = size >= io_detail::Progress::kStep ? 0.5 : 0.0;
  io_detail::Progress progress(callback, size, "reading", 0, header_share);
  const io_detail::MappedFile file(path);
  progress.add(file.bytes().size());
  return impl(io_detail::FileSource(file), path.string(), path.parent_path(),
              callback ? &callback : nullptr, header_share, summary);
}

}  // namespace

ImageData read_nrrd(const std::filesystem::path& path, const ProgressCallback& progress) {
  return read_raw_volume(path, progress, [](auto&&... a) { return read_nrrd_impl(a...); });
}

ImageData read_metaimage(std::span<const std::byte> data, std::string_view name,
                         const std::filesystem::path& base_dir) {
  return read_metaimage_impl(data, std::string(name), base_dir);
}

ImageData read_metaimage(const std::filesystem::path& path, const ProgressCallback& progress) {
  return read_raw_volume(path, progress, [](auto&&... a) { return read_metaimage_impl(a...); });
}

namespace io_detail {

DatasetSummary summarize_raw_volume(const std::filesystem::path& path,
                                    const ProgressCallback& progress, bool nrrd) {
  DatasetSummary s;
  if (nrrd) {
    (void)read_raw_volume(path, progress, [](auto&&... a) { return read_nrrd_impl(a...); }, &s);
  } else {
    (void)read_raw_volume(path, progress, [](auto&&... a) { return read_metaimage_impl(a...); },
                          &s);
  }
  return s;
}

}  // namespace io_detail

}  // namespace isoforge
