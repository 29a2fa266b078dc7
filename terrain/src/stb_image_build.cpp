// Fuzz builds only (SHORE_FUZZ=ON): Debian's stb_image (libstb-dev's header) compiled into
// shore_terrain instead of linking libstb, so that the fuzzers instrument its PNG decoder.
#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>
