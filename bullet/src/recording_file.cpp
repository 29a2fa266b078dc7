#include "shore/bullet/recording_file.h"

#include <zstd.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "shore/bullet/body_state.h"
#include "shore/core/byte_io.h"
#include "shore/core/error.h"
#include "shore/core/hash.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace {

constexpr char kMagic[8] = {'S', 'H', 'O', 'R', 'E', 'R', 'E', 'C'};
constexpr std::uint32_t kVersion = Recording::kVersion;
constexpr std::uint32_t kByteOrderMark = 0x01020304u;
constexpr std::size_t kHeaderBytes = 8 + 4 + 4 + 4 + 8 + 8;
constexpr std::uint64_t kMaxRawBytes = std::uint64_t{1} << 32;
// zstd's best ratio: a 128 KiB block from a 4-byte RLE block (soil_delta.cpp says the same).
constexpr std::uint64_t kMaxRatio = 131072 / 4;

std::uint64_t checksum(const unsigned char* data, std::size_t size) {
  StateHash h;
  h.add_bytes(data, size);
  return h.value();
}

void put_string(ByteWriter& w, const std::string& s) {
  w.put(static_cast<std::uint32_t>(s.size()));
  w.bytes.insert(w.bytes.end(), s.begin(), s.end());
}
void put_bytes(ByteWriter& w, std::span<const unsigned char> b) {
  w.put(static_cast<std::uint64_t>(b.size()));
  w.bytes.insert(w.bytes.end(), b.begin(), b.end());
}

/// Reads the raw layout; every size is checked against what is left before it is used.
class RawReader : public ByteReader {
 public:
  RawReader(std::span<const unsigned char> raw, const std::string& source) : ByteReader(raw, source), raw_(raw) {}
  std::string string(const char* what) {
    const auto size = get<std::uint32_t>(what);
    if (size > remaining()) fail(std::string("truncated (ends inside ") + what + ")");
    const std::span<const unsigned char> s = take(size);
    return {reinterpret_cast<const char*>(s.data()), s.size()};
  }
  std::span<const unsigned char> bytes(const char* what) {
    const auto size = get<std::uint64_t>(what);
    if (size > remaining()) fail(std::string("truncated (ends inside ") + what + ")");
    return take(static_cast<std::size_t>(size));
  }
  std::span<const unsigned char> take(std::size_t size) {
    const std::span<const unsigned char> out = raw_.subspan(raw_.size() - remaining(), size);
    skip(size, "bytes");
    return out;
  }

 private:
  std::span<const unsigned char> raw_;
};

/// The checked, decompressed raw bytes of a recording file, and its version.
std::vector<unsigned char> unpack(std::span<const unsigned char> bytes, const std::string& source,
                                  std::uint32_t& version_out) {
  ByteReader r(bytes, source);
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    r.fail("not a Shore recording (magic \"SHOREREC\" missing)");
  if (bytes.size() < kHeaderBytes + 8) r.fail("truncated (" + std::to_string(bytes.size()) + " bytes)");
  r.skip(sizeof kMagic, "magic");
  const auto version = r.get<std::uint32_t>("version");
  if (version == 1)
    r.fail("recording version 1 (written before recordings held water), this build reads versions " +
           std::to_string(Recording::kOldestVersion) + " to " + std::to_string(kVersion) +
           " only: record the run again");
  if (version < Recording::kOldestVersion || version > kVersion)
    r.fail("unsupported recording version " + std::to_string(version) + " (this build reads " +
           std::to_string(Recording::kOldestVersion) + " to " + std::to_string(kVersion) + ")");
  if (r.get<std::uint32_t>("byte-order mark") != kByteOrderMark) r.fail("written with the other byte order");
  const auto scalar = r.get<std::uint32_t>("precision");
  const auto raw_size = r.get<std::uint64_t>("header"), frame_size = r.get<std::uint64_t>("header");
  if (frame_size != bytes.size() - kHeaderBytes - 8)
    r.fail("truncated or padded (a compressed body of " + std::to_string(frame_size) + " bytes in a file of " +
           std::to_string(bytes.size()) + ")");
  std::uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + bytes.size() - 8, sizeof stored);
  if (stored != checksum(bytes.data(), bytes.size() - 8)) r.fail("checksum mismatch (corrupt)");
  if (scalar != scalar_bytes())
    r.fail("written by a build with " + std::to_string(8 * std::uint64_t{scalar}) +
           "-bit Bullet scalars, this one uses " + std::to_string(8 * scalar_bytes()) +
           "-bit (SHORE_DOUBLE_PRECISION differs)");
  if (raw_size > kMaxRawBytes || raw_size > frame_size * kMaxRatio ||
      ZSTD_getFrameContentSize(bytes.data() + kHeaderBytes, frame_size) != raw_size)
    r.fail("corrupt (a raw size of " + std::to_string(raw_size) + " bytes for a zstd frame of " +
           std::to_string(frame_size) + ")");
  std::vector<unsigned char> raw(raw_size);
  const std::size_t got = ZSTD_decompress(raw.data(), raw.size(), bytes.data() + kHeaderBytes, frame_size);
  if (ZSTD_isError(got) != 0) r.fail(std::string("zstd: ") + ZSTD_getErrorName(got));
  if (got != raw.size()) r.fail("corrupt (decompressed size differs from the header's)");
  version_out = version;
  return raw;
}

}  // namespace

std::vector<btScalar> Recording::body_scalars(const Frame& f, const std::string& source) const {
  const ByteReader r(f.bodies, source);
  std::vector<btScalar> v(f.bodies.size() / sizeof(btScalar));
  if (!v.empty()) std::memcpy(v.data(), f.bodies.data(), v.size() * sizeof(btScalar));
  for (const btScalar x : v)
    if (!std::isfinite(static_cast<double>(x)))
      r.fail("frame at substep " + std::to_string(f.substep) + ": corrupt (a non-finite body state)");
  return v;
}

std::uint32_t Recording::MultiBodyLayout::collider_count() const {
  // Nonzero (read_recording refuses all but 1), so that any flags written read back framed alike.
  return static_cast<std::uint32_t>(colliders.size() - std::count(colliders.begin(), colliders.end(), std::uint8_t{0}));
}

std::uint64_t Recording::MultiBodyLayout::scalars() const {
  return std::uint64_t{values} + std::uint64_t{kTransformScalars} * collider_count();
}

std::string Recording::MultiBodyLayout::describe(std::uint64_t k) const {
  if (k < values) return "state value " + std::to_string(k) + " of " + std::to_string(values);
  std::uint64_t collider = (k - values) / kTransformScalars;
  for (std::size_t part = 0; part < colliders.size(); ++part) {
    if (colliders[part] == 0) continue;
    if (collider-- == 0)
      return (part == 0 ? std::string("the base") : "link " + std::to_string(part - 1)) + "'s collider world transform";
  }
  return "scalar " + std::to_string(k);  // past the layout: not reached for a frame read by read_recording
}

std::vector<btScalar> Recording::multibody_scalars(const Frame& f, const std::string& source) const {
  const ByteReader r(f.multibodies, source);
  std::vector<btScalar> v(f.multibodies.size() / sizeof(btScalar));
  if (!v.empty()) std::memcpy(v.data(), f.multibodies.data(), v.size() * sizeof(btScalar));
  std::size_t at = 0;
  for (std::size_t m = 0; m < multibodies.size(); ++m) {
    const std::uint64_t n = multibodies[m].scalars();
    for (std::uint64_t k = 0; k < n && at + k < v.size(); ++k)
      if (!std::isfinite(static_cast<double>(v[at + k])))
        r.fail("frame at substep " + std::to_string(f.substep) + ", multibody " + std::to_string(m) + ": corrupt (" +
               multibodies[m].describe(k) + " is " + std::to_string(static_cast<double>(v[at + k])) + ", not finite)");
    at += static_cast<std::size_t>(n);
  }
  return v;
}

std::uint64_t Recording::wheel_bytes() const {
  std::uint64_t wheels = 0;
  for (const std::uint32_t n : vehicle_wheels) wheels += n;
  return wheels * kWheelScalars * sizeof(btScalar);
}

std::vector<btScalar> Recording::wheel_scalars(const Frame& f, const std::string& source) const {
  std::vector<btScalar> v(f.wheels.size() / sizeof(btScalar));
  if (!v.empty()) std::memcpy(v.data(), f.wheels.data(), v.size() * sizeof(btScalar));
  std::size_t at = 0;
  for (std::size_t m = 0; m < vehicle_wheels.size(); ++m)
    for (std::uint32_t w = 0; w < vehicle_wheels[m]; ++w)
      for (int k = 0; k < kWheelScalars; ++k, ++at)
        if (at < v.size() && !std::isfinite(static_cast<double>(v[at])))
          throw FileError(source + ": frame at substep " + std::to_string(f.substep) + ", vehicle " +
                          std::to_string(m) + ", wheel " + std::to_string(w) + ": corrupt (its world transform holds " +
                          std::to_string(static_cast<double>(v[at])) + ", not finite)");
  return v;
}

std::vector<unsigned char> write_recording(const Recording& rec, int compression_level) {
  const std::string field = "bullet::write_recording(rec)";
  if (rec.version < Recording::kOldestVersion || rec.version > kVersion)
    throw InvalidSetting(field + ".version", std::to_string(rec.version),
                         "2 to " + std::to_string(kVersion) + " (the versions this build reads)");
  const bool multibodies = rec.version >= 3;
  if (!multibodies && !rec.multibodies.empty())
    throw InvalidSetting(field + ".version", "2 with " + std::to_string(rec.multibodies.size()) + " multibodies",
                         "version 3 or later (version 2 holds no multibodies)");
  const bool wheels = rec.version >= 4;
  if (!wheels && !rec.vehicle_wheels.empty())
    throw InvalidSetting(
        field + ".version",
        std::to_string(rec.version) + " with " + std::to_string(rec.vehicle_wheels.size()) + " vehicles",
        "version 4 or later (earlier versions hold no wheels)");
  std::uint64_t multibody_bytes = 0;
  for (const Recording::MultiBodyLayout& m : rec.multibodies) multibody_bytes += m.scalars() * sizeof(btScalar);
  for (const Recording::Frame& f : rec.frames) {
    const std::string frame = field + ".frames[substep " + std::to_string(f.substep) + "]";
    if (f.multibodies.size() != multibody_bytes)
      throw InvalidSetting(frame + ".multibodies", std::to_string(f.multibodies.size()) + " bytes",
                           std::to_string(multibody_bytes) + " (the multibodies' layouts)");
    if (f.wheels.size() != rec.wheel_bytes())
      throw InvalidSetting(frame + ".wheels", std::to_string(f.wheels.size()) + " bytes",
                           std::to_string(rec.wheel_bytes()) + " (the vehicles' wheel counts)");
  }
  ByteWriter raw;
  put_string(raw, rec.scene);
  raw.put(rec.seconds), raw.put(rec.substep), raw.put(rec.cell);
  put_string(raw, rec.material);
  raw.put(static_cast<std::uint8_t>(rec.smoke ? 1 : 0));
  raw.put(static_cast<std::int32_t>(rec.substeps));
  raw.put(rec.state_hash);
  put_bytes(raw, rec.initial);
  raw.put(static_cast<std::uint32_t>(rec.terrain_generations.size()));
  for (const std::uint64_t g : rec.terrain_generations) raw.put(g);
  raw.put(rec.waters);
  if (multibodies) {
    raw.put(static_cast<std::uint32_t>(rec.multibodies.size()));
    for (const Recording::MultiBodyLayout& m : rec.multibodies) {
      raw.put(m.links), raw.put(m.values);
      for (const std::uint8_t c : m.colliders) raw.put(c);
    }
  }
  if (wheels) {
    raw.put(static_cast<std::uint32_t>(rec.vehicle_wheels.size()));
    for (const std::uint32_t n : rec.vehicle_wheels) raw.put(n);
  }
  raw.put(static_cast<std::uint32_t>(rec.frames.size()));
  for (const Recording::Frame& f : rec.frames) {
    raw.put(static_cast<std::int32_t>(f.substep));
    for (const auto& d : f.terrain_deltas) put_bytes(raw, d);
    raw.put(f.body_count);
    raw.bytes.insert(raw.bytes.end(), f.bodies.begin(), f.bodies.end());
    raw.bytes.insert(raw.bytes.end(), f.multibodies.begin(), f.multibodies.end());
    raw.bytes.insert(raw.bytes.end(), f.wheels.begin(), f.wheels.end());
    for (const auto& x : f.water_diffs) put_bytes(raw, x);
  }

  ByteWriter out;
  for (char ch : kMagic) out.put(ch);
  out.put(rec.version), out.put(kByteOrderMark), out.put(scalar_bytes());
  out.put(static_cast<std::uint64_t>(raw.bytes.size()));
  const std::size_t frame_at = out.bytes.size() + 8;
  out.bytes.resize(frame_at + ZSTD_compressBound(raw.bytes.size()));
  const std::size_t frame = ZSTD_compress(out.bytes.data() + frame_at, out.bytes.size() - frame_at, raw.bytes.data(),
                                          raw.bytes.size(), compression_level);
  if (ZSTD_isError(frame) != 0)
    throw FileError(std::string("recording: zstd failed (") + ZSTD_getErrorName(frame) + ")");
  out.bytes.resize(frame_at + frame);
  const auto frame_size = static_cast<std::uint64_t>(frame);
  std::memcpy(out.bytes.data() + frame_at - 8, &frame_size, sizeof frame_size);
  out.put(checksum(out.bytes.data(), out.bytes.size()));
  return std::move(out.bytes);
}

namespace {
/// Version 3's multibody layouts; returns the bytes each frame holds of them. Each layout's
/// frame bytes are checked against what is left (every frame holds them), so their sum
/// stays below the multibody count times the raw size: no overflow.
std::uint64_t read_multibody_layouts(RawReader& r, std::vector<Recording::MultiBodyLayout>& out) {
  const auto count = r.get<std::uint32_t>("multibody count");
  // A layout holds at least its two counts and its base's collider flag.
  if (count > r.remaining() / 9) r.fail("corrupt (" + std::to_string(count) + " multibodies)");
  out.resize(count);
  std::uint64_t bytes = 0;
  for (std::size_t m = 0; m < out.size(); ++m) {
    Recording::MultiBodyLayout& l = out[m];
    const std::string which = "multibody " + std::to_string(m);
    l.links = r.get<std::uint32_t>("a multibody's link count");
    l.values = r.get<std::uint32_t>("a multibody's state value count");
    if (std::uint64_t{l.links} + 1 > r.remaining())
      r.fail(which + ": truncated (" + std::to_string(l.links) + " links' collider flags)");
    l.colliders.resize(std::size_t{l.links} + 1);
    for (std::size_t part = 0; part < l.colliders.size(); ++part) {
      l.colliders[part] = r.get<std::uint8_t>("a collider flag");
      if (l.colliders[part] > 1)
        r.fail(which + ": corrupt (collider flag of " + (part == 0 ? "the base" : "link " + std::to_string(part - 1)) +
               " is " + std::to_string(l.colliders[part]) + ", allowed 0 or 1)");
    }
    const std::uint64_t b = l.scalars() * sizeof(btScalar);
    if (b > r.remaining()) r.fail(which + ": corrupt (" + std::to_string(l.values) + " state values per frame)");
    bytes += b;
  }
  return bytes;
}

/// Version 4's wheel counts, one per vehicle; returns the bytes each frame holds of them.
/// Checked against what is left (every frame holds them): no overflow.
std::uint64_t read_vehicle_wheels(RawReader& r, Recording& rec) {
  const auto count = r.get<std::uint32_t>("vehicle count");
  if (count > r.remaining() / 4) r.fail("corrupt (" + std::to_string(count) + " vehicles)");
  rec.vehicle_wheels.resize(count);
  for (std::size_t v = 0; v < rec.vehicle_wheels.size(); ++v) {
    rec.vehicle_wheels[v] = r.get<std::uint32_t>("a vehicle's wheel count");
    const std::uint64_t wheel = Recording::kWheelScalars * sizeof(btScalar);
    if (rec.vehicle_wheels[v] > r.remaining() / wheel)
      r.fail("vehicle " + std::to_string(v) + ": corrupt (" + std::to_string(rec.vehicle_wheels[v]) + " wheels)");
  }
  const std::uint64_t bytes = rec.wheel_bytes();
  if (bytes > r.remaining()) r.fail("corrupt (the vehicles' wheels per frame exceed the file)");
  return bytes;
}
}  // namespace

Recording read_recording(std::span<const unsigned char> file, const std::string& source) {
  Recording rec;
  rec.raw = unpack(file, source, rec.version);
  RawReader r(rec.raw, source);
  rec.scene = r.string("the scene name");
  rec.seconds = r.get<double>("options"), rec.substep = r.get<double>("options"), rec.cell = r.get<double>("options");
  rec.material = r.string("options");
  const auto smoke = r.get<std::uint8_t>("options");
  // (found by fuzz_recording: any nonzero byte read as true and was written back as 1)
  if (smoke > 1) r.fail("corrupt options (smoke flag " + std::to_string(smoke) + ", allowed 0 or 1)");
  rec.smoke = smoke == 1;
  rec.substeps = r.get<std::int32_t>("substeps");
  if (rec.substeps < 1) r.fail("corrupt (" + std::to_string(rec.substeps) + " substeps)");
  rec.state_hash = r.get<std::uint64_t>("the final state hash");
  rec.initial = r.bytes("the initial checkpoint");
  const auto terrains = r.get<std::uint32_t>("terrain count");
  if (terrains > r.remaining() / sizeof(std::uint64_t)) r.fail("corrupt (" + std::to_string(terrains) + " terrains)");
  rec.terrain_generations.resize(terrains);
  for (auto& g : rec.terrain_generations) g = r.get<std::uint64_t>("a terrain's generation");
  rec.waters = r.get<std::uint32_t>("water count");
  const std::uint64_t multibody_bytes = rec.version >= 3 ? read_multibody_layouts(r, rec.multibodies) : 0;
  const std::uint64_t wheel_bytes = rec.version >= 4 ? read_vehicle_wheels(r, rec) : 0;
  const auto frames = r.get<std::uint32_t>("frame count");
  if (frames == 0) r.fail("truncated (no frames)");
  // A frame holds at least its substep, a u64 size per terrain and water, its body count
  // and its multibodies' and wheels' states.
  const std::uint64_t frame_min = 4 + 8 * (std::uint64_t{terrains} + rec.waters) + 4 + multibody_bytes + wheel_bytes;
  if (frames > r.remaining() / frame_min) r.fail("corrupt (" + std::to_string(frames) + " frames)");
  rec.frames.resize(frames);
  int last = 0;
  for (Recording::Frame& f : rec.frames) {
    f.substep = r.get<std::int32_t>("a frame's substep");
    if (f.substep <= last || f.substep > rec.substeps)
      r.fail("corrupt (frame at substep " + std::to_string(f.substep) + " after " + std::to_string(last) + " of " +
             std::to_string(rec.substeps) + ")");
    last = f.substep;
    const std::string where = "frame at substep " + std::to_string(f.substep);
    f.terrain_deltas.resize(terrains);
    for (auto& d : f.terrain_deltas) d = r.bytes("a terrain delta");
    f.body_count = r.get<std::uint32_t>("the body count");
    const std::uint64_t body_bytes = std::uint64_t{f.body_count} * Recording::kBodyScalars * sizeof(btScalar);
    if (body_bytes > r.remaining()) r.fail(where + ": truncated (" + std::to_string(f.body_count) + " bodies)");
    f.bodies = r.take(static_cast<std::size_t>(body_bytes));
    if (multibody_bytes > r.remaining()) r.fail(where + ": truncated (ends inside the multibodies' states)");
    f.multibodies = r.take(static_cast<std::size_t>(multibody_bytes));
    if (wheel_bytes > r.remaining()) r.fail(where + ": truncated (ends inside the wheels)");
    f.wheels = r.take(static_cast<std::size_t>(wheel_bytes));
    f.water_diffs.resize(rec.waters);
    for (auto& x : f.water_diffs) x = r.bytes("a water state");
  }
  if (r.remaining() != 0) r.fail("corrupt (bytes after the last frame)");
  if (last != rec.substeps)
    r.fail("truncated (the last frame is at substep " + std::to_string(last) + " of " + std::to_string(rec.substeps) +
           ")");
  return rec;
}

namespace {
// A frame's water bytes: the state XOR the previous one (0 past the previous state's end),
// grouped by their place in an 8-byte word: byte k goes to plane k % 8, the planes in
// order. The states are mostly doubles, whose sign and exponent bytes rarely change between
// frames while their mantissas do; grouped, the unchanged bytes make long runs of zeros for
// zstd. Exact for any bytes and length. (Measured on pond and beach: the planes take 2 and
// 11 % off the plain XOR's file; u64 differences of the words, zigzagged and at the best of
// the 8 alignments, were 5 % larger than the planes: the waves move by far more than a few
// units of the doubles' last place between frames.)
constexpr std::size_t kPlanes = 8;
}  // namespace

const std::vector<unsigned char>& StateChain::next(std::span<const unsigned char> frame) {
  prev_.resize(frame.size());
  std::size_t o = 0;
  for (std::size_t p = 0; p < kPlanes; ++p)
    for (std::size_t k = p; k < frame.size(); k += kPlanes) prev_[k] ^= frame[o++];
  return prev_;
}

std::vector<unsigned char> StateChain::encode(const std::vector<unsigned char>& state) {
  std::vector<unsigned char> out(state.size());
  std::size_t o = 0;
  for (std::size_t p = 0; p < kPlanes; ++p)
    for (std::size_t k = p; k < state.size(); k += kPlanes)
      out[o++] = k < prev_.size() ? state[k] ^ prev_[k] : state[k];
  prev_ = state;
  return out;
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
