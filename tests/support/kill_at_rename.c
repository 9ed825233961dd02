/* LD_PRELOAD shim for tests of "a bake is replaced whole": with PUFF_KILL_AT_RENAME=K in
 * the environment, the process sends itself SIGKILL at its K-th rename(2) call (1-based), before
 * the rename happens: the same as `kill -9` arriving between two renames. Without the variable,
 * or K < 1, renames pass through. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <signal.h>
#include <stdlib.h>

int rename(const char* from, const char* to) {
  static int (*real)(const char*, const char*) = 0;
  static long count = 0;
  if (!real) real = (int (*)(const char*, const char*))dlsym(RTLD_NEXT, "rename");
  const char* k = getenv("PUFF_KILL_AT_RENAME");
  if (k && ++count == atol(k)) raise(SIGKILL);
  return real(from, to);
}
