// Trimming the process's resident set once start-up is over (issue 18: memory).
#pragma once

#include <cstddef>

namespace lumar {

// Unmaps, from this process's page tables, the resident pages of read-only file mappings that
// hold nothing but the file's own bytes (no page written or copied on write): code and
// constants of the libraries, most of which only start-up runs (libLLVM, which llvmpipe uses
// to compile shaders: ~56 MB resident after the first frames, none of it run once every
// shader variant exists). The pages stay in the page cache; a library that runs again faults
// back exactly the pages it uses. Returns the bytes dropped (0 where /proc is unreadable).
size_t dropCleanFilePages();

} // namespace lumar
