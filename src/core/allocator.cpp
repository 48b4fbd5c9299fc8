#include "isoquad/remesh.hpp"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace isoquad {

void tune_allocator() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 256 << 20);  // blocks up to 256 MB from the heap, reused
  mallopt(M_TRIM_THRESHOLD, 1 << 30);    // free heap top kept up to 1 GB
#endif
}

}  // namespace isoquad
