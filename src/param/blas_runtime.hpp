// The BLAS under the sparse solvers. CHOLMOD's supernodal factorization spends its time in
// dense BLAS calls, in whichever BLAS the system provides: Debian switches libblas.so.3 between
// the reference BLAS and OpenBLAS builds (scripts/install-deps installs OpenBLAS's threaded
// build, which factors the bunny's seam system 2.5 times faster than the reference BLAS).
#pragma once

#include <mutex>

namespace isoquad {

// A lock to hold around a factorization or solve that calls BLAS. The first call sets OpenBLAS,
// if it is the BLAS loaded, to one thread: isoquad's own threads already use the cores, and the
// floating-point result then does not depend on how many cores the machine has. The lock is
// held only under OpenBLAS's sequential build, which shares its work buffers between callers
// without a lock (two concurrent factorizations failed there); otherwise it is empty.
std::unique_lock<std::mutex> blas_section();

}  // namespace isoquad
