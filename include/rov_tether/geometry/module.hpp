#pragma once
/**
 * Optional modules: parts of rov_tether that bring large libraries with them (meshes: FCL and assimp;
 * cameras: OpenCV) are shared libraries of their own, loaded with dlopen the first time a program asks for
 * them, so a program that uses neither does not load those libraries at its start (the runner's start-up,
 * docs/benchmarks.md).
 */

#include <string>

namespace rov_tether
{

/**
 * The C-linkage function `symbol` of the module `library` (a file name, "librov_tether_mesh.so"): from the
 * program itself when it links the module (or its code, -rdynamic) already, else from the module loaded
 * once from the directory of the library holding this function (the devel or install space's lib), else by
 * the loader's search path. Null with the loader's error in `error`. Thread-safe; a module stays loaded.
 */
void* moduleFunction(const char* library, const char* symbol, std::string* error);

}  // namespace rov_tether
