#include "common.hpp"

#include <fmt/core.h>

#include <charconv>
#include <cmath>
#include <string>

#include "isoforge/core/error.hpp"
#include "isoforge/implicit/parse.hpp"

namespace isoforge::cli {

CLI::Validator integer_in(std::int64_t min, std::int64_t max) {
  const std::string range = max == INT64_MAX ? fmt::format(">= {}", min)
                                             : fmt::format("in [{}, {}]", min, max);
  return CLI::Validator(
      [min, max, range](std::string& s) -> std::string {
        const char* b = s.data();
        const char* e = b + s.size();
        if (b != e && *b == '+') ++b;
        std::int64_t v = 0;
        const auto [p, ec] = std::from_chars(b, e, v);
        if (b == e || p != e || ec == std::errc::invalid_argument) {
          return fmt::format("must be an integer {}, got '{}'", range, s);
        }
        if (ec == std::errc::result_out_of_range || v < min || v > max) {
          return fmt::format("must be an integer {}, got {}", range, s);
        }
        s = std::to_string(v);  // what CLI11 converts: no sign, no leading zeros
        return {};
      },
      max == INT64_MAX ? fmt::format(">={}", min) : fmt::format("{}..{}", min, max));
}

FileFormat format_of(const std::string& path) {
  try {
    return format_from_path(path);
  } catch (const Error& e) {
    throw UsageError(e.what());
  }
}

ImplicitFunction parse_function(const std::string& expression, const char* option) {
  try {
    return parse_implicit(expression);
  } catch (const Error& e) {
    throw UsageError(option, e.what());
  }
}

Bounds parse_bounds(const std::vector<double>& b, const char* option) {
  if (b.size() != 6) throw UsageError(std::string(option) + ": needs 6 numbers: xmin xmax ymin ymax zmin zmax");
  Bounds out;
  out.min = {b[0], b[2], b[4]};
  out.max = {b[1], b[3], b[5]};
  for (int a = 0; a < 3; ++a) {
    if (!(out.min[a] <= out.max[a]) || !std::isfinite(out.min[a]) || !std::isfinite(out.max[a])) {
      throw UsageError(std::string(option) + ": min must not exceed max (axis " + std::to_string(a) + ")");
    }
  }
  return out;
}

Dims parse_dims(const std::vector<Index>& d, const char* option) {
  if (d.size() == 1) return {d[0], d[0], d[0]};
  if (d.size() == 3) return {d[0], d[1], d[2]};
  throw UsageError(std::string(option) + ": give one number (a cube) or three");
}

Bounds grown(const Bounds& b, double pad) {
  Bounds r = b;
  r.min = b.min - Vec3{pad, pad, pad};
  r.max = b.max + Vec3{pad, pad, pad};
  return r;
}

double elapsed_ms(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace isoforge::cli
