#pragma once
// Precision guard. Bullet's btScalar is float or double (BT_USE_DOUBLE_PRECISION); an
// application and Shore built with different choices would disagree on every object's
// layout and corrupt memory silently. Every shore::bullet symbol therefore lives in an
// inline namespace named after the precision: a mismatched application fails at link
// time with an undefined reference to shore::bullet::abi_f32::... or ...::abi_f64::...

#include <LinearMath/btScalar.h>

#ifdef BT_USE_DOUBLE_PRECISION
#define SHORE_BULLET_ABI abi_f64
#else
#define SHORE_BULLET_ABI abi_f32
#endif

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

/// True if this build of shore::bullet uses Bullet's double-precision btScalar.
bool built_with_double_precision() noexcept;

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
