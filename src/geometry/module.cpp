#include "rov_tether/geometry/module.hpp"

#include <dlfcn.h>

#include <mutex>

namespace rov_tether
{

void* moduleFunction(const char* library, const char* symbol, std::string* error)
{
  // dlopen and dlsym are thread-safe, dlerror is per thread; the lock keeps a first load from racing.
  static std::mutex mutex;
  const std::lock_guard<std::mutex> lock(mutex);
  if (void* found = dlsym(RTLD_DEFAULT, symbol))
  {
    return found;
  }
  std::string path = library;
  Dl_info self{};
  if (dladdr(reinterpret_cast<void*>(&moduleFunction), &self) != 0 && self.dli_fname != nullptr)
  {
    const std::string here = self.dli_fname;
    const std::size_t slash = here.rfind('/');
    if (slash != std::string::npos)
    {
      path = here.substr(0, slash + 1) + library;
    }
  }
  void* module = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (module == nullptr && path != library)
  {
    module = dlopen(library, RTLD_NOW | RTLD_LOCAL);
  }
  if (module == nullptr)
  {
    const char* why = dlerror();
    *error = why != nullptr ? why : std::string(library) + ": cannot be loaded";
    return nullptr;
  }
  void* found = dlsym(module, symbol);
  if (found == nullptr)
  {
    const char* why = dlerror();
    *error = why != nullptr ? why : std::string(symbol) + " not found in " + library;
  }
  return found;
}

}  // namespace rov_tether
