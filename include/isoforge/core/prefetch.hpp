#pragma once
/// \file
/// `prefetch(p)`: asks the CPU to bring the cache line holding `p` closer (a hint, no effect on
/// results). For passes that will read scattered samples a little later, such as the ends of
/// crossed edges in a large volume.

namespace isoforge {

/// Prefetches the cache line of `p` for reading. GCC deletes a loop whose only effect is
/// `__builtin_prefetch` (the builtin counts as free of side effects, and loops may be assumed
/// to terminate), so on x86 the instruction is written out.
inline void prefetch(const void* p) {
#if defined(__x86_64__) || defined(__i386__)
  asm volatile("prefetcht0 %0" : : "m"(*static_cast<const char*>(p)));
#else
  __builtin_prefetch(p);
#endif
}

}  // namespace isoforge
