#pragma once
// Random damage to file bytes, for tests that readers reject corrupt input with an Error and
// never crash or throw anything else.

#include <gtest/gtest.h>

#include <cstddef>
#include <exception>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "isoforge/core/error.hpp"

namespace isoforge::test {

/// `bytes` after `edits` random edits, each one of: a random byte, a byte of `alphabet` (the
/// format's own syntax, which gets past the first checks more often), a deletion, an insertion
/// of a byte of `alphabet`.
inline std::vector<std::byte> mutate(std::vector<std::byte> bytes, std::mt19937& rng, int edits,
                                     std::string_view alphabet) {
  for (int e = 0; e < edits && !bytes.empty(); ++e) {
    const std::size_t at = rng() % bytes.size();
    const auto syntax = static_cast<std::byte>(alphabet[rng() % alphabet.size()]);
    switch (rng() % 4) {
      case 0:
        bytes[at] = static_cast<std::byte>(rng() % 256);
        break;
      case 1:
        bytes[at] = syntax;
        break;
      case 2:
        bytes.erase(bytes.begin() + static_cast<std::ptrdiff_t>(at));
        break;
      default:
        bytes.insert(bytes.begin() + static_cast<std::ptrdiff_t>(at), syntax);
    }
  }
  return bytes;
}

/// Fails the test if read(bytes) throws anything but an `Error`; returns whether it threw one.
template <class Read>
bool rejects_only_with_error(Read&& read, const std::vector<std::byte>& bytes,
                             const std::string& what) {
  try {
    (void)read(bytes);
    return false;
  } catch (const Error&) {
    return true;
  } catch (const std::exception& e) {
    ADD_FAILURE() << what << ": non-isoforge exception: " << e.what();
    return false;
  }
}

}  // namespace isoforge::test
