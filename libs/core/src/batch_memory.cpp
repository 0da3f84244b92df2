#include "terralod/core/batch_memory.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace terralod {

void keepFreedMemoryForReuse() {
#if defined(__GLIBC__)
  // Setting either fixes both (glibc stops adapting them), so both are set.
  mallopt(M_MMAP_THRESHOLD, 64 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
#endif
}

}  // namespace terralod
