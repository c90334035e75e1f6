// A fault injector for the output tests, loaded with LD_PRELOAD: once WRITE_FAULT_BYTES bytes
// have gone to files (not stdin/stdout/stderr), every further write fails with errno
// WRITE_FAULT_ERRNO (default ENOSPC), as on a full disk. Covers write, writev, pwrite and fwrite
// (glibc's stdio writes through an internal call that LD_PRELOAD cannot see). With
// WRITE_FAULT_COUNT=PATH, the bytes written to files are written to PATH at exit (to find a
// run's total, and so the budgets that fail at each of its files).
#include <dlfcn.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/uio.h>
#include <unistd.h>

extern "C" {

static long long written;

static int fault_now(int fd, size_t bytes) {
  static long long limit = -2;
  if (limit == -2) {
    const char* text = getenv("WRITE_FAULT_BYTES");
    limit = text ? atoll(text) : -1;
  }
  if (fd <= 2 || bytes == 0) return 0;
  if (limit < 0 || written + static_cast<long long>(bytes) <= limit) {
    written += static_cast<long long>(bytes);
    return 0;
  }
  const char* code = getenv("WRITE_FAULT_ERRNO");
  errno = code ? atoi(code) : ENOSPC;
  return 1;
}

ssize_t write(int fd, const void* data, size_t bytes) {
  static ssize_t (*real)(int, const void*, size_t);
  if (!real)
    real = reinterpret_cast<ssize_t (*)(int, const void*, size_t)>(dlsym(RTLD_NEXT, "write"));
  if (fault_now(fd, bytes)) return -1;
  return real(fd, data, bytes);
}

ssize_t pwrite(int fd, const void* data, size_t bytes, off_t at) {
  static ssize_t (*real)(int, const void*, size_t, off_t);
  if (!real)
    real =
        reinterpret_cast<ssize_t (*)(int, const void*, size_t, off_t)>(dlsym(RTLD_NEXT, "pwrite"));
  if (fault_now(fd, bytes)) return -1;
  return real(fd, data, bytes, at);
}

ssize_t writev(int fd, const struct iovec* parts, int count) {
  static ssize_t (*real)(int, const struct iovec*, int);
  if (!real)
    real = reinterpret_cast<ssize_t (*)(int, const struct iovec*, int)>(dlsym(RTLD_NEXT, "writev"));
  size_t bytes = 0;
  for (int k = 0; k < count; ++k) bytes += parts[k].iov_len;
  if (fault_now(fd, bytes)) return -1;
  return real(fd, parts, count);
}

size_t fwrite(const void* data, size_t size, size_t count, FILE* file) {
  static size_t (*real)(const void*, size_t, size_t, FILE*);
  if (!real)
    real = reinterpret_cast<size_t (*)(const void*, size_t, size_t, FILE*)>(
        dlsym(RTLD_NEXT, "fwrite"));
  if (fault_now(fileno(file), size * count)) return 0;
  return real(data, size, count, file);
}

__attribute__((destructor)) static void report_count() {
  const char* path = getenv("WRITE_FAULT_COUNT");
  if (!path) return;
  FILE* file = fopen(path, "w");
  if (!file) return;
  fprintf(file, "%lld\n", written);
  fclose(file);
}

}  // extern "C"
