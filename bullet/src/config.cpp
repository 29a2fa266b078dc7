#include "shore/bullet/config.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

bool built_with_double_precision() noexcept {
#ifdef BT_USE_DOUBLE_PRECISION
  return true;
#else
  return false;
#endif
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
