#include "working_set.h"

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <sys/mman.h>

namespace lumar {
namespace {

struct Mapping {
    uintptr_t start = 0, end = 0;
    bool readOnlyFile = false; // r?x or r-- private file mapping, never writable
    size_t resident = 0;       // bytes
    size_t changed = 0;        // anonymous (copied on write) or dirty bytes: not the file's own
};

size_t kilobytes(const std::string& line)
{
    std::istringstream in(line);
    std::string field;
    size_t kb = 0;
    in >> field >> kb;
    return kb * 1024;
}

std::vector<Mapping> fileMappings()
{
    std::vector<Mapping> mappings;
    std::ifstream smaps("/proc/self/smaps");
    std::string line;
    while (std::getline(smaps, line)) {
        unsigned long start = 0, end = 0; // %lx's type, as wide as a pointer on Linux's ABIs
        char perms[5] = {};
        unsigned long long offset = 0;
        unsigned long long inode = 0;
        int pathStart = 0;
        // "start-end perms offset dev inode path": a mapping's header; the rest are its fields.
        if (std::sscanf(line.c_str(), "%lx-%lx %4s %llx %*s %llu %n", &start, &end, perms, &offset, &inode,
                        &pathStart) >= 5 &&
            line.find(" kB") == std::string::npos) {
            Mapping m;
            m.start = uintptr_t(start);
            m.end = uintptr_t(end);
            // Private (p), not writable, backed by a file (inode), a path that is not a [pseudo].
            m.readOnlyFile = perms[0] == 'r' && perms[1] == '-' && perms[3] == 'p' && inode != 0 && pathStart > 0 &&
                             size_t(pathStart) < line.size() && line[size_t(pathStart)] == '/';
            mappings.push_back(m);
            continue;
        }
        if (mappings.empty())
            continue;
        Mapping& m = mappings.back();
        if (line.starts_with("Rss:"))
            m.resident = kilobytes(line);
        else if (line.starts_with("Anonymous:") || line.starts_with("Private_Dirty:") ||
                 line.starts_with("Shared_Dirty:"))
            m.changed += kilobytes(line);
    }
    return mappings;
}

} // namespace

size_t dropCleanFilePages()
{
    size_t dropped = 0;
    for (const Mapping& m : fileMappings()) {
        // A page written or copied on write (relocations, a debugger's breakpoint) would be lost:
        // such a mapping stays as it is.
        if (!m.readOnlyFile || m.changed != 0 || m.resident == 0)
            continue;
        // On a private file mapping MADV_DONTNEED only unmaps: the next access reads the file's
        // bytes again, from the page cache.
        if (madvise(reinterpret_cast<void*>(m.start), m.end - m.start, MADV_DONTNEED) == 0)
            dropped += m.resident;
    }
    return dropped;
}

} // namespace lumar
