#pragma once
// Internal: Bullet values and variable-length arrays in checkpoint bytes (shore/core/byte_io.h).
// btScalars are written raw: a checkpoint carries its writer's precision and refuses the other.

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include <BulletCollision/CollisionShapes/btCollisionShape.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>
#include <LinearMath/btTransform.h>

#include "coupling_util.h"
#include "shore/bullet/config.h"
#include "shore/bullet/ground_frame.h"
#include "shore/core/byte_io.h"
#include "shore/core/envelope.h"
#include "shore/core/vec3.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

inline void put_vector(ByteWriter& w, const btVector3& v) {
  for (int k = 0; k < 3; ++k) w.put(v[k]);
}
inline void put_transform(ByteWriter& w, const btTransform& t) {
  for (int r = 0; r < 3; ++r) put_vector(w, t.getBasis()[r]);
  put_vector(w, t.getOrigin());
}
inline btVector3 get_vector(ByteReader& r, const char* what) {
  btVector3 v;
  for (int k = 0; k < 3; ++k) v[k] = r.get<btScalar>(what);
  return v;
}
inline btTransform get_transform(ByteReader& r, const char* what) {
  btMatrix3x3 m;
  for (int row = 0; row < 3; ++row) m[row] = get_vector(r, what);
  const btVector3 o = get_vector(r, what);
  return btTransform(m, o);
}

inline bool finite(const btTransform& t) {
  return finite(t.getOrigin()) && finite(t.getBasis()[0]) && finite(t.getBasis()[1]) && finite(t.getBasis()[2]);
}

/// A window of columns (first index in x and y, size) with its lower and upper values:
/// the couplings' envelopes.
inline void put_window(ByteWriter& w, const EnvelopeRaster& e) {
  w.put(e.i0), w.put(e.j0), w.put(e.nx), w.put(e.ny);
  w.put_array(e.lower), w.put_array(e.upper);
}
/// Reads put_window's form; FileError for a negative size or NaN values (the arrays' sizes
/// are for the caller to check against nx * ny).
inline void get_window(ByteReader& r, EnvelopeRaster& e);

inline void put_vec3(ByteWriter& w, const Vec3& v) { w.put(v.x), w.put(v.y), w.put(v.z); }
inline Vec3 get_vec3(ByteReader& r, const char* what) {
  Vec3 v;
  v.x = r.get<double>(what), v.y = r.get<double>(what), v.z = r.get<double>(what);
  return v;
}

/// An array written field by field: a u64 count, then put_one(w, value) for each value.
template <class T, class PutOne>
void put_fields(ByteWriter& w, const std::vector<T>& values, PutOne&& put_one) {
  w.put(static_cast<std::uint64_t>(values.size()));
  for (const T& v : values) put_one(w, v);
}
/// Reads put_fields' form, get_one(r) returning each value; `bytes_each` is the fewest bytes
/// one value takes, so a count the bytes left cannot hold is refused before anything is
/// allocated.
template <class T, class GetOne>
void get_fields(ByteReader& r, std::vector<T>& values, std::size_t bytes_each, const char* what, GetOne&& get_one) {
  const auto count = r.get<std::uint64_t>(what);
  if (count > r.remaining() / bytes_each)
    r.fail(std::string(what) + " claims " + std::to_string(count) + " values, more than the bytes left");
  values.clear();
  values.reserve(static_cast<std::size_t>(count));
  for (std::uint64_t k = 0; k < count; ++k) values.push_back(get_one(r));
}

/// A state's header: 8 magic bytes, u32 version, u32 sizeof(btScalar).
inline void put_header(ByteWriter& w, const char (&magic)[8], std::uint32_t version) {
  for (char c : magic) w.put(c);
  w.put(version), w.put(static_cast<std::uint32_t>(sizeof(btScalar)));
}
/// Checks put_header's bytes: FileError naming what the bytes should be, the version or the precision.
/// Checks magic, version (oldest to newest) and precision; returns the version.
inline std::uint32_t check_header(ByteReader& r, const char (&magic)[8], std::uint32_t oldest, std::uint32_t newest,
                                  const char* what) {
  std::array<char, 8> m{};
  for (char& c : m) c = r.get<char>("magic");
  if (std::memcmp(m.data(), magic, sizeof magic) != 0)
    r.fail(std::string("not ") + what + " (magic " + std::string(magic, sizeof magic) + " missing)");
  const auto v = r.get<std::uint32_t>("version");
  if (v < oldest || v > newest)
    r.fail("unsupported version " + std::to_string(v) + " of " + what + " (this build reads " +
           (oldest == newest ? std::to_string(newest) : std::to_string(oldest) + " to " + std::to_string(newest)) +
           ")");
  if (const auto scalar = r.get<std::uint32_t>("precision"); scalar != sizeof(btScalar))
    r.fail("written with " + std::to_string(8 * scalar) + "-bit Bullet scalars, this build uses " +
           std::to_string(8 * sizeof(btScalar)) + "-bit");
  return v;
}
inline void check_header(ByteReader& r, const char (&magic)[8], std::uint32_t version, const char* what) {
  (void)check_header(r, magic, version, version, what);
}

/// The ground frame a coupling's state was saved with (from version `since` of its format;
/// older states were all Z-up): a checkpoint restores only into the same frame.
inline void put_frame(ByteWriter& w, const GroundFrame& frame) { put_transform(w, frame.to_world()); }
inline void check_frame(ByteReader& r, std::uint32_t version, std::uint32_t since, const GroundFrame& frame) {
  const btTransform own = frame.to_world();
  const btTransform saved = version >= since ? get_transform(r, "ground frame") : btTransform::getIdentity();
  bool same = true;  // element by element: btVector3's == also compares its unused fourth lane
  for (int k = 0; k < 3; ++k)
    for (int c = 0; c < 3; ++c) same = same && saved.getBasis()[k][c] == own.getBasis()[k][c];
  for (int k = 0; k < 3; ++k) same = same && saved.getOrigin()[k] == own.getOrigin()[k];
  if (!same)
    r.fail(std::string("was saved with another ground frame (origin ") + std::to_string(double(saved.getOrigin().x())) +
           ", " + std::to_string(double(saved.getOrigin().y())) + ", " + std::to_string(double(saved.getOrigin().z())) +
           ", up " + std::to_string(double(saved.getBasis()[0][2])) + ", " +
           std::to_string(double(saved.getBasis()[1][2])) + ", " + std::to_string(double(saved.getBasis()[2][2])) +
           ") than this coupling's settings().frame");
}

/// The body's collision shape type (-1: none): saved states check they meet the same body.
inline int shape_type(const btCollisionObject& b) {
  return b.getCollisionShape() ? b.getCollisionShape()->getShapeType() : -1;
}

/// Reads ByteWriter::put_array's form of any length the bytes can hold (a corrupt count
/// is refused before anything is allocated).
template <class T>
requires std::is_trivially_copyable_v<T>
void get_any_array(ByteReader& r, std::vector<T>& v, const char* what) {
  const auto count = r.get<std::uint64_t>(what);
  if (count > r.remaining() / sizeof(T))
    r.fail(std::string(what) + " claims " + std::to_string(count) + " values, more than the bytes left");
  v.resize(static_cast<std::size_t>(count));
  for (T& x : v) x = r.get<T>(what);
}

inline void get_window(ByteReader& r, EnvelopeRaster& e) {
  e.i0 = r.get<std::int64_t>("envelope"), e.j0 = r.get<std::int64_t>("envelope");
  e.nx = r.get<int>("envelope"), e.ny = r.get<int>("envelope");
  if (e.nx < 0 || e.ny < 0 || e.nx > (1 << 20) || e.ny > (1 << 20))
    r.fail("envelope of size " + std::to_string(e.nx) + " x " + std::to_string(e.ny) + " (0 to 2^20 columns a side)");
  constexpr std::int64_t kMaxColumn = std::int64_t{1} << 52;  // the terrain's own bound on column indices
  if (e.i0 < -kMaxColumn || e.i0 > kMaxColumn || e.j0 < -kMaxColumn || e.j0 > kMaxColumn)
    r.fail("envelope at column (" + std::to_string(e.i0) + ", " + std::to_string(e.j0) + ") beyond index 2^52");
  get_any_array(r, e.lower, "envelope");
  get_any_array(r, e.upper, "envelope");
  for (const auto* values : {&e.lower, &e.upper})
    for (double v : *values)
      if (std::isnan(v)) r.fail("envelope holds NaN");
}

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
