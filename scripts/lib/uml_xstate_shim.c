// Preloaded into User-Mode Linux (Debian 12's user-mode-linux, kernel 6.1) by
// scripts/lib/uml.sh, for hosts whose XSAVE state is larger than the buffer UML keeps for
// each thread (AVX-512, AMX). There the host's PTRACE_SETREGSET of NT_X86_XSTATE accepts
// only a whole XSAVE buffer and fails with EFAULT, and UML panics as it starts init
// ("userspace - ptrace set fp regs failed, errno = 14").
//
// Each PTRACE_GETREGSET of NT_X86_XSTATE into a buffer of UML's is made whole into a
// shadow of that buffer, and UML gets its part; each PTRACE_SETREGSET from that buffer
// writes the shadow back whole with UML's part on top. So the state UML has no room for
// (the upper halves of the zmm registers, zmm16-31, the opmask registers, AMX) is kept for
// each thread as the host kernel would keep it. Where UML's buffer is already whole, the
// calls pass through unchanged.
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ptrace.h>
#include <sys/types.h>
#include <sys/uio.h>

#define NT_X86_XSTATE_NOTE 0x202
#define LARGEST_XSTATE (64 * 1024)
#define BUCKETS 4096

typedef long (*ptrace_function)(enum __ptrace_request, pid_t, void*, void*);

struct shadow {
  const void* uml_buffer;
  struct shadow* next;
  unsigned char state[];
};

static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
static ptrace_function real_ptrace;
static size_t host_size;  // the host's whole XSAVE buffer, once known
static struct shadow* buckets[BUCKETS];

static struct shadow** bucket_of(const void* uml_buffer) {
  return &buckets[((uintptr_t)uml_buffer >> 4) % BUCKETS];
}

static struct shadow* find(const void* uml_buffer) {
  for (struct shadow* s = *bucket_of(uml_buffer); s != NULL; s = s->next) {
    if (s->uml_buffer == uml_buffer) return s;
  }
  return NULL;
}

static struct shadow* find_or_add(const void* uml_buffer) {
  struct shadow* s = find(uml_buffer);
  if (s != NULL) return s;
  s = calloc(1, sizeof *s + host_size);
  if (s == NULL) return NULL;
  s->uml_buffer = uml_buffer;
  s->next = *bucket_of(uml_buffer);
  *bucket_of(uml_buffer) = s;
  return s;
}

// The host's size: a PTRACE_GETREGSET shortens iov_len to the whole regset.
static long learn_host_size(pid_t pid) {
  static unsigned char probe[LARGEST_XSTATE];
  struct iovec whole = {probe, sizeof probe};
  const long result = real_ptrace(PTRACE_GETREGSET, pid, (void*)NT_X86_XSTATE_NOTE, &whole);
  if (result == 0) host_size = whole.iov_len;
  return result;
}

static long get_xstate(pid_t pid, struct iovec* uml) {
  if (host_size == 0 && learn_host_size(pid) != 0) return -1;
  if (uml->iov_len >= host_size) return real_ptrace(PTRACE_GETREGSET, pid, (void*)NT_X86_XSTATE_NOTE, uml);
  struct shadow* s = find_or_add(uml->iov_base);
  if (s == NULL) return real_ptrace(PTRACE_GETREGSET, pid, (void*)NT_X86_XSTATE_NOTE, uml);
  struct iovec whole = {s->state, host_size};
  const long result = real_ptrace(PTRACE_GETREGSET, pid, (void*)NT_X86_XSTATE_NOTE, &whole);
  if (result != 0) return result;
  memcpy(uml->iov_base, s->state, uml->iov_len);
  return 0;
}

static long set_xstate(pid_t pid, struct iovec* uml) {
  if (host_size == 0 && learn_host_size(pid) != 0) return -1;
  if (uml->iov_len >= host_size) return real_ptrace(PTRACE_SETREGSET, pid, (void*)NT_X86_XSTATE_NOTE, uml);
  struct shadow* s = find(uml->iov_base);
  if (s == NULL) {
    // A buffer UML filled itself (a new thread): the rest as the thread has it now.
    s = find_or_add(uml->iov_base);
    if (s == NULL) return real_ptrace(PTRACE_SETREGSET, pid, (void*)NT_X86_XSTATE_NOTE, uml);
    struct iovec whole = {s->state, host_size};
    if (real_ptrace(PTRACE_GETREGSET, pid, (void*)NT_X86_XSTATE_NOTE, &whole) != 0) return -1;
  }
  memcpy(s->state, uml->iov_base, uml->iov_len);
  struct iovec whole = {s->state, host_size};
  return real_ptrace(PTRACE_SETREGSET, pid, (void*)NT_X86_XSTATE_NOTE, &whole);
}

long ptrace(enum __ptrace_request request, ...) {
  va_list arguments;
  va_start(arguments, request);
  const pid_t pid = va_arg(arguments, pid_t);
  void* const address = va_arg(arguments, void*);
  void* const data = va_arg(arguments, void*);
  va_end(arguments);

  pthread_mutex_lock(&lock);
  if (real_ptrace == NULL) real_ptrace = (ptrace_function)dlsym(RTLD_NEXT, "ptrace");
  long result;
  if ((request == PTRACE_GETREGSET || request == PTRACE_SETREGSET) && (uintptr_t)address == NT_X86_XSTATE_NOTE) {
    const int saved_errno = errno;
    result = request == PTRACE_GETREGSET ? get_xstate(pid, data) : set_xstate(pid, data);
    if (result == 0) errno = saved_errno;
  } else {
    result = real_ptrace(request, pid, address, data);
  }
  pthread_mutex_unlock(&lock);
  return result;
}
