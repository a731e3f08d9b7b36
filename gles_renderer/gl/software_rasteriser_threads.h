// How many threads Mesa's llvmpipe rasterises with, chosen before the first EGL display
// starts it.
#pragma once

namespace lumar {

// Sets LP_NUM_THREADS (llvmpipe's own variable; other drivers ignore it) to one more than the
// cores this process may run on, unless the environment already sets it. Call it first thing
// in main(), before any thread starts: setenv is not safe alongside getenv in another thread.
// Returns the value in effect.
int chooseSoftwareRasteriserThreads();

} // namespace lumar
