#pragma once
// How much memory the OS can still give this process: the one figure the
// up-front memory checks (film size, photon maps) compare their estimates
// with, so that a request too large fails with a clear message instead of
// std::bad_alloc after minutes of work.
namespace lb {

// MemAvailable from /proc/meminfo, or all physical memory if it is missing.
double availableMemoryBytes();

}  // namespace lb
