#pragma once
// Allocator setting for the batch tools that run many smoother problems in one
// process (Monte Carlo studies, campaigns).
//
// The iSAM2 smoother frees many small blocks (factors, keys, Jacobian blocks) and
// then asks for larger ones (the dense system of a clique). With glibc's default
// malloc, the small blocks wait unmerged in "fast bins", and each larger request
// first merges all of them (malloc_consolidate): on a 30-min Monte Carlo flight
// about 5-7 % of the CPU time (ppp_bench_mc_throughput). Without fast bins the
// small blocks are merged when freed, once. What is computed does not change, only
// where the memory comes from.
//
// Where gperftools' tcmalloc is installed, the build links these tools with it
// instead (CMakeLists.txt): its per-thread caches of small blocks cost less again
// (about 15 % of a Monte Carlo flight's CPU time); this setting then changes nothing.
namespace ppp {

/// Turns glibc's fast bins off (mallopt M_MXFAST = 0) for the whole process; call
/// it first thing in main. Does nothing with another C library. Returns whether
/// the setting was applied.
bool useAllocatorWithoutFastBins();

}  // namespace ppp
