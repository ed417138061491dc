#pragma once
/// \file
/// Memory guards. Entry points that allocate in proportion to a request (dense volumes, narrow
/// bands) first estimate the bytes and refuse at once, with a message naming the size, when they
/// exceed the machine's physical memory — instead of growing to gigabytes and ending in
/// `std::bad_alloc`.

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace isoforge {

/// The machine's physical memory in bytes (sysconf: physical pages × page size); 0 if unknown.
[[nodiscard]] std::uint64_t physical_memory();

/// A byte count for messages, in decimal units with at most 3 significant digits: "512 B",
/// "3.2 kB", "108 GB", "4 PB".
[[nodiscard]] std::string format_bytes(double bytes);

/// Grid dimensions for messages: "3000³" for a cube, else "300 x 200 x 100".
[[nodiscard]] std::string format_dims(const std::array<std::int64_t, 3>& dims);

/// Refuses a request that cannot fit: \throw Error "<what> needs <bytes>; this machine has
/// <physical memory>" when `bytes` exceeds the physical memory (nothing if that is unknown).
/// `bytes` is an estimate, a double so that products of huge dimensions cannot overflow; NaN is
/// refused too. Example: `require_memory(3000.0 * 3000 * 3000 * 4, "sample: a 3000³ Float32
/// volume")` → "sample: a 3000³ Float32 volume needs 108 GB; this machine has 24.6 GB".
void require_memory(double bytes, std::string_view what);

/// `require_memory` for a dense volume of dims[0] x dims[1] x dims[2] samples of
/// `bytes_per_sample` bytes each (all its arrays), described as "<what>: a <dims> <type> volume".
/// \throw Error e.g. "sample: a 3000³ Float32 volume needs 108 GB; this machine has 24.6 GB".
void require_volume_memory(std::string_view what, const std::array<std::int64_t, 3>& dims,
                           std::string_view type, double bytes_per_sample);

}  // namespace isoforge
