// tinyobjloader's implementation, compiled here with the fuzzers' instrumentation (see CMakeLists.txt).
#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>
