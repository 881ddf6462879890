// Only in the fuzz build (tests/fuzz/fuzz.cmake, FOVLAB_FUZZ=ON): tinyobjloader's implementation,
// compiled here with coverage and sanitizers, so that fovlab_obj_fuzz sees into the OBJ and MTL
// parsing instead of the uninstrumented libtinyobjloader.so (whose definitions these replace).
#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>
