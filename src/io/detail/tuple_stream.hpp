#pragma once
// Private: the values of an array handed on in pieces as they are decoded, for readers that
// summarise a file (io::summarize_file) instead of loading it. Bytes arrive in pieces of any
// size; whole tuples are byte-swapped to host order and passed to a consumer, a partial tuple
// is kept for the next piece. Memory: one piece, never the array.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "io/detail/file_source.hpp"
#include "isoforge/core/data_array.hpp"

namespace isoforge::io_detail {

class Progress;

class TupleStream {
 public:
  /// The largest piece a reader should decode at once.
  static constexpr std::size_t kPiece = std::size_t{8} << 20;
  using Consumer = std::function<void(const std::byte* tuples, std::size_t count)>;

  TupleStream(ScalarType type, int components, bool swap, Consumer consume);

  /// A buffer for the next `n` bytes of the stream.
  std::byte* window(std::size_t n);
  /// The `n` bytes of the last window are written: whole tuples are consumed.
  void filled(std::size_t n);
  /// Bytes of an incomplete last tuple (0 when the stream ended on a tuple).
  [[nodiscard]] std::size_t pending() const { return carry_; }
  [[nodiscard]] std::uint64_t tuples() const { return tuples_; }

 private:
  std::size_t elem_, unit_;
  bool swap_;
  Consumer consume_;
  std::vector<std::byte> buffer_;
  std::size_t carry_ = 0;
  std::uint64_t tuples_ = 0;
};

/// Streams `n` bytes at `from` (inside `src.bytes`) through `stream` in pieces read with
/// FileSource::copy (the mapped pages stay untouched); `progress` (may be null) is set to
/// `progress_base` + the bytes done after each piece.
void stream_bytes(const FileSource& src, const std::byte* from, std::size_t n, TupleStream& stream,
                  Progress* progress = nullptr, std::uint64_t progress_base = 0);

}  // namespace isoforge::io_detail
