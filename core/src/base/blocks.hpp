// Long loops as a series of calls, for WebAssembly engines' tiering.
//
// A WebAssembly engine runs a function's first calls as quickly compiled
// baseline code and swaps in optimised code only at a later call (V8 has no
// on-stack replacement for WebAssembly). A loop over a million items in one
// call therefore runs at baseline speed to its end, several times slower
// than the same loop in a later call (tests/bench/README.md, "The first read
// in WebAssembly, in blocks", has the profile). for_blocks runs such a loop
// as calls of one function that is not inlined, a block of items per call,
// so that the engine can switch to optimised code after the first blocks.
// Native builds inline it: the same loop, split in two levels.
#pragma once

#include <cstddef>

namespace cdt3d {

/// Items per call of for_blocks' body: enough that the call costs nothing,
/// few enough that the first blocks are a small share of a large loop.
inline constexpr size_t kBlockItems = 4096;

template <typename Index, typename Body>
bool run_block(Body& body, Index begin, Index end) {
  return body(begin, end);
}

/// Calls body(begin, end) on consecutive blocks covering [0, n) in order,
/// until it returns false; returns false if it did. body returns bool and
/// takes two Index (size_t for containers, uint64_t for counts read from a
/// file, which may not fit a 32-bit size_t).
template <typename Index, typename Body>
bool for_blocks(Index n, Body&& body) {
#ifdef __EMSCRIPTEN__
  // Through a pointer read from memory: Binaryen's inliner (wasm-opt, at
  // link) does not keep a noinline attribute, but cannot see through this.
  bool (*volatile call)(Body&, Index, Index) = &run_block<Index, Body>;
#else
  bool (*call)(Body&, Index, Index) = &run_block<Index, Body>;
#endif
  const Index block = kBlockItems;
  for (Index b = 0; b < n; b += block) {
    if (!call(body, b, n - b > block ? b + block : n)) return false;
  }
  return true;
}

}  // namespace cdt3d
