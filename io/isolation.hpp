// Reading hostile HDF5 metadata in a child process (docs/reliability.md "Damaged and hostile
// HDF5 files").
//
// Why: the HDF5 library trusts the bytes it reads. Sixteen random bytes over a recording's
// metadata can send it into a segmentation fault in its global heap (H5HG_read) while a
// string attribute is read, or into allocating gigabytes; no check allanlot makes before the
// library reads can rule that out, and a crash in allanlot's own process ends the whole lot.
//
// How: before the process opens an HDF5 file that carries no seal (every input recording, and
// results files of earlier versions), the same reading of its metadata runs once in a forked
// child, bounded in address space (setrlimit RLIMIT_AS) and CPU time (RLIMIT_CPU) and killed
// after a wall-clock bound. The parent learns only how the child ended: normally (the parent
// then reads the file itself, the same code on the same bytes), with an io::Error (re-thrown
// in the parent unchanged, without reading anything), or killed by a signal or a bound (an
// io::Error naming the file and the signal). Sealed files are checked byte for byte before the
// library reads them (io/seal.hpp) and need no child.
//
// fork(2) and not exec: the library is used from GoogleTest programs and the Python module, which
// have no allanlot binary to exec. The child calls no OpenMP and only the HDF5 library and the
// allocator, which glibc's fork keeps usable; callers fork only while no other thread of theirs is
// inside the HDF5 library (allanlot calls it from one thread at a time).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>

namespace allanlot::io {

struct IsolationLimits {
  /// Address space the child may add to what it inherits (the metadata of a recording or a
  /// results file needs a few MiB; a damaged one asked the library for 14.7 GB).
  std::uint64_t extra_address_space = std::uint64_t{2} << 30;
  /// CPU time and wall-clock time of the child.
  std::chrono::seconds cpu{60};
  std::chrono::seconds wall{120};
};

/// Runs `work` (a reading of `file`) in a child process within `limits`. Returns normally when
/// `work` returned; throws the io::Error that `work` threw (file, dataset and reason as thrown);
/// throws io::Error naming `file` when the child died (a signal, a bound) or could not be
/// started. Inside such a child, runs `work` in the process itself (nothing is isolated twice).
void run_isolated(const std::string& file, const std::function<void()>& work,
                  const IsolationLimits& limits = {});

/// True in the child process of run_isolated, and after read_in_process().
bool in_isolated_child();

/// From now on, this process reads as the child does: nothing is isolated. For the fuzz targets
/// over allanlot's own code on well-formed files (fuzz/fuzz_recording.cpp), whose crashes must
/// reach the fuzzer rather than end a child.
void read_in_process();

}  // namespace allanlot::io
