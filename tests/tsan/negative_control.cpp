// The negative control of the `tsan` tests: a data race TSan must report whatever the timing.
// The main thread writes gShared after starting the thread that writes it, and before joining
// it, so no happens-before orders the two writes. The ctest passes only on TSan's report.
#include <cstdio>
#include <thread>

int gShared = 0; // not static: the writes must stay

int main()
{
    std::thread other([] { gShared = 1; });
    gShared = 2;
    other.join();
    std::printf("negative control: gShared = %d (TSan must have reported a data race)\n", gShared);
    return 0;
}
