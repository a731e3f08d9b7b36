// The C library's own functions behind the ones this library interposes, found with
// dlsym(RTLD_NEXT). The device code calls these for its own memfds, so it never re-enters an
// interposer (which would take the registry lock twice).
#pragma once

#include <cstddef>
#include <cstdio>

#include <poll.h>
#include <sys/select.h>
#include <sys/stat.h>
#include <sys/types.h>

namespace lumar::vcam::real {

int open(const char* path, int flags, mode_t mode);
int open64(const char* path, int flags, mode_t mode);
int openat(int directory, const char* path, int flags, mode_t mode);
int openat64(int directory, const char* path, int flags, mode_t mode);
int close(int fd);
int ioctl(int fd, unsigned long request, void* arg);
void* mmap(void* address, size_t length, int protection, int flags, int fd, off_t offset);
void* mmap64(void* address, size_t length, int protection, int flags, int fd, off64_t offset);
int munmap(void* address, size_t length);
int poll(pollfd* fds, nfds_t count, int timeoutMs);
int select(int count, fd_set* readSet, fd_set* writeSet, fd_set* exceptSet, timeval* timeout);
int stat(const char* path, struct stat* out);
int stat64(const char* path, struct stat64* out);
FILE* fopen(const char* path, const char* mode);
FILE* fopen64(const char* path, const char* mode);

} // namespace lumar::vcam::real
