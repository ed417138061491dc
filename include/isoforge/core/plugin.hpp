#pragma once
/// \file
/// The parts of isoforge that load on demand. In a shared build the code that needs OpenVDB
/// (libisoforge_vdb) and Ceres (libisoforge_fit) are libraries of their own, which libisoforge
/// loads the first time one of their functions is called, so that a program which never uses
/// them does not pay for loading those dependencies (docs/architecture.md); the `isoforge`
/// program loads its OpenVDB commands (a module beside libisoforge) the same way. Nothing to do
/// for a user: calls go through libisoforge's own functions.

namespace isoforge {

/// The address of the function `symbol` in the shared library `name` (a file name), loaded
/// once: from the directory of libisoforge, else wherever the dynamic loader finds it.
/// \throw Error "<what>: cannot load <name>: <reason>" if neither loads or it lacks `symbol`.
[[nodiscard]] void* plugin_symbol(const char* name, const char* symbol, const char* what);

}  // namespace isoforge
