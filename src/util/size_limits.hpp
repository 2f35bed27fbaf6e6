#pragma once
// How large a job may grow, checked before the work and before any sample is
// decoded.
//
// A small file can claim a huge size (a decompression bomb: a 90 KB PNG whose
// header says 30000x30000, a 100-byte NRRD header of 400^3 voxels). Readers
// measure the input from its header (OpenImageIO's ImageSpec, the NRRD
// header's sizes, the count of points read) and refuse it against a limit in
// one line before anything is decoded; the commands size the memory a job
// will hold and refuse it when that cannot fit the memory available. The same
// check serves the output limits (--max-pixels, --max-voxels) and the input
// limits (--max-input-pixels, --max-input-voxels, --max-input-points).
//
// Errors: throws ddt::Error with a one-line message.

#include <initializer_list>
#include <string>

namespace ddt {

// Bytes of physical memory, and of memory available now (Linux's
// MemAvailable; the physical memory where it cannot be read).
long long physical_memory();
long long available_memory();
// Bytes of this process resident now (Linux's /proc/self/statm; 0 where
// it cannot be read): the libraries' pages and what the job holds so far.
long long resident_memory();

// A memory size as a user writes it: bytes ("1500000000"), or a number
// with K, M, G or T (powers of 1024; "2G", "512M", "1.5G"; an optional
// trailing B or iB). Throws ddt::Error for anything else, 0 or negative
// sizes, or more than 2^62 bytes.
long long parse_memory_size(const std::string& text);

// The input limits' defaults, sized to the machine's physical memory:
//   pixels: memory / 32, so the decoded input (up to 4 float channels,
//           16 bytes a pixel) takes at most half of it (24 GB: 805 million
//           pixels, about 28000x28000);
//   voxels: memory / 1024, so the tetrahedralization's working set (about
//           0.5 KB an input voxel, docs/volumes.md) takes at most half of it
//           (24 GB: 25 million voxels, about 290^3);
//   points: memory / 1024, the same for the triangulation of scattered
//           points and their values.
long long default_max_input_pixels();
long long default_max_input_voxels();
long long default_max_input_points();

// Throws "<what> <size> exceeds <option> <limit>; give <option> <count>
// to allow it" when count > limit; e.g. check_size_limit("input 'a.png'",
// "30000x30000", 9e8, limit, "--max-input-pixels"). count < 0 stands for
// a count past 2^63 (no value to give then).
void check_size_limit(const std::string& what, const std::string& size, long long count, long long limit,
                      const std::string& option);

// The product of `sizes`, or -1 when it passes 2^63 (a header's claim).
long long checked_product(std::initializer_list<long long> sizes);

// Throws "<job> needs at least N MB of memory, M MB are available" when
// `bytes` (the memory the job will hold, counted by the caller) exceeds
// available_memory().
void check_memory_fits(const std::string& job, double bytes);

}  // namespace ddt
