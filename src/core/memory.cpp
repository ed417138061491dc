#include "isoforge/core/memory.hpp"

#include <fmt/core.h>
#include <unistd.h>

#include <cmath>

#include "isoforge/core/error.hpp"

namespace isoforge {

std::uint64_t physical_memory() {
  const long pages = ::sysconf(_SC_PHYS_PAGES);
  const long page_size = ::sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page_size <= 0) return 0;
  return static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page_size);
}

std::string format_bytes(double bytes) {
  static constexpr const char* kUnits[] = {"B", "kB", "MB", "GB", "TB", "PB", "EB"};
  constexpr int kLast = static_cast<int>(std::size(kUnits)) - 1;
  int u = 0;
  while (u < kLast && std::abs(bytes) >= 999.5) {  // 999.6 kB would print as "1e+03 kB"
    bytes /= 1000;
    ++u;
  }
  return fmt::format("{:.3g} {}", bytes, kUnits[u]);
}

std::string format_dims(const std::array<std::int64_t, 3>& dims) {
  if (dims[0] == dims[1] && dims[1] == dims[2]) return fmt::format("{}³", dims[0]);
  return fmt::format("{} x {} x {}", dims[0], dims[1], dims[2]);
}

void require_memory(double bytes, std::string_view what) {
  const std::uint64_t have = physical_memory();
  if (have == 0) return;
  if (!(bytes <= static_cast<double>(have))) {
    throw Error(fmt::format("{} needs {}; this machine has {}", what, format_bytes(bytes),
                            format_bytes(static_cast<double>(have))));
  }
}

void require_volume_memory(std::string_view what, const std::array<std::int64_t, 3>& dims,
                           std::string_view type, double bytes_per_sample) {
  const double samples =
      static_cast<double>(dims[0]) * static_cast<double>(dims[1]) * static_cast<double>(dims[2]);
  if (samples * bytes_per_sample <= static_cast<double>(physical_memory())) return;  // fast path
  require_memory(samples * bytes_per_sample,
                 fmt::format("{}: a {} {} volume", what, format_dims(dims), type));
}

}  // namespace isoforge
