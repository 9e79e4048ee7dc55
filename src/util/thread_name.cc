#include "util/thread_name.h"

#include <algorithm>
#include <string>

#ifdef __linux__
#include <pthread.h>
#endif

namespace memloop {

void NameThisThread(const char* role) {
#ifdef __linux__
  std::string name = std::string("memloop-") + role;
  name.resize(std::min<size_t>(name.size(), 15));  // the kernel's limit, without the '\0'
  pthread_setname_np(pthread_self(), name.c_str());
#else
  (void)role;
#endif
}

}  // namespace memloop
