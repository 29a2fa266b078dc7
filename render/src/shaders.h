#pragma once
// GLSL 330 core sources of the renderer's passes (the "#version" line is added by gl::program).

namespace shore::render::shaders {

/// Lighting shared by every lit surface: hemisphere ambient, the sun with a 3 x 3 PCF shadow.
inline constexpr const char* kLighting = R"(
uniform vec3 uSunDir;            // towards the sun
uniform sampler2DShadow uShadow;
uniform int uShadowOn;
uniform float uShadowTexel;
float sun_visibility(vec4 lp, vec3 n) {
  if (uShadowOn == 0) return 1.0;
  vec3 p = lp.xyz / lp.w * 0.5 + 0.5;
  if (p.x < 0.0 || p.x > 1.0 || p.y < 0.0 || p.y > 1.0 || p.z > 1.0) return 1.0;
  float bias = 0.0015 + 0.003 * (1.0 - max(dot(n, uSunDir), 0.0));
  float s = 0.0;
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y) s += texture(uShadow, vec3(p.xy + vec2(x, y) * uShadowTexel, p.z - bias));
  return s / 9.0;
}
vec3 lit(vec3 albedo, vec3 n, vec4 lp) {
  float sun = max(dot(n, uSunDir), 0.0) * sun_visibility(lp, n);
  vec3 ambient = mix(vec3(0.30, 0.28, 0.26), vec3(0.42, 0.47, 0.56), 0.5 + 0.5 * n.z);
  return albedo * (ambient + vec3(1.0, 0.95, 0.86) * 0.80 * sun);
}
vec3 sky_colour(vec3 dir) {
  float e = dir.z;
  // Below the horizon a pale haze, darkening slowly: the pictures look down on the scene, so
  // most of their background is this, and it must not read as ground.
  vec3 horizon = vec3(0.80, 0.86, 0.92), zenith = vec3(0.30, 0.50, 0.80), haze = vec3(0.66, 0.71, 0.76);
  return e >= 0.0 ? mix(horizon, zenith, smoothstep(0.0, 0.7, e)) : mix(horizon, haze, smoothstep(0.0, 0.8, -e));
}
)";

/// What the surface vertex shader hands the terrain and water fragment shaders, and the
/// colour maps (rows: 0 diverging, 1 height, 2 water).
inline constexpr const char* kFieldFragmentInputs = R"(
in vec3 vPos;
in vec3 vNormal;
in float vValue;
in float vDelta;
in vec2 vColumn;
in vec4 vLight;
out vec4 oColour;
uniform sampler2D uLut;
vec3 lut(float row, float t) { return texture(uLut, vec2(clamp(t, 0.0, 1.0) * (255.0 / 256.0) + 0.5 / 256.0, (row + 0.5) / 3.0)).rgb; }
)";

/// A soil or water mesh chunk: position, the surface's normal at the node, and per vertex
/// (height - reference, a second value, the node's column i and j). Slopes are steepened by
/// uSlopeGain for shading.
inline constexpr const char* kSurfaceVertex = R"(
layout(location = 0) in vec3 aPos;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec4 aExtra;
uniform float uSlopeGain;
uniform mat4 uViewProj;
uniform mat4 uLightViewProj;
out vec3 vPos;
out vec3 vNormal;
out float vValue;
out float vDelta;
out vec2 vColumn;
out vec4 vLight;
void main() {
  vNormal = normalize(vec3(aNormal.xy * uSlopeGain, aNormal.z));
  vPos = aPos;
  vDelta = aExtra.x;
  vValue = aExtra.y;
  vColumn = aExtra.zw;
  vLight = uLightViewProj * vec4(vPos, 1.0);
  gl_Position = uViewProj * vec4(vPos, 1.0);
}
)";

inline constexpr const char* kTerrainFragment = R"(
uniform int uMode;            // 0 natural, 1 deformation, 2 sinkage, 3 height
uniform float uScale;
uniform vec2 uHeightRange;
uniform vec3 uTint;
uniform int uTileColumns;     // 0: no tile borders
uniform int uEdges;           // 1: the mesh's edges pass
uniform int uMapOn;           // 1: colour by the material map (natural mode)
uniform usampler2D uMap;      // palette index per column of the drawn region
uniform ivec2 uMapOrigin;     // the region's first column
uniform vec3 uPalette[256];   // each palette entry's colour
void main() {
  if (uEdges == 1) { oColour = vec4(0.12, 0.10, 0.08, 1.0); return; }
  vec3 n = normalize(vNormal);
  vec3 albedo = uTint;
  if (uMapOn == 1) {  // the nearest column's material: borders stay sharp on coarse triangles
    ivec2 c = clamp(ivec2(floor(vColumn + 0.5)) - uMapOrigin, ivec2(0), textureSize(uMap, 0) - 1);
    albedo = uPalette[texelFetch(uMap, c, 0).r];
  }
  if (uMode == 1) albedo = lut(0.0, 0.5 + 0.5 * vDelta / uScale);
  else if (uMode == 2) albedo = lut(0.0, 0.5 - 0.5 * vValue / uScale);
  else if (uMode == 3) albedo = lut(1.0, (vPos.z - uHeightRange.x) / max(uHeightRange.y - uHeightRange.x, 1e-9));
  vec3 c = lit(albedo, n, vLight);
  if (uTileColumns > 0) {
    vec2 g = vColumn / float(uTileColumns);
    vec2 w = fwidth(g) * 1.2;
    vec2 d = abs(fract(g - 0.5) - 0.5);
    if (d.x < w.x || d.y < w.y) c = mix(c, vec3(0.05, 0.05, 0.05), 0.7);
  }
  oColour = vec4(c, 1.0);
}
)";

inline constexpr const char* kWaterFragment = R"(
uniform int uMode;            // 0 natural, 1 height, 2 vertical velocity
uniform float uScale;
uniform vec3 uEye;
uniform int uEdges;           // 1: the mesh's edges pass
void main() {
  if (uEdges == 1) { oColour = vec4(0.05, 0.12, 0.20, 0.9); return; }
  vec3 n = normalize(vNormal);
  vec3 v = normalize(uEye - vPos);
  float sun = sun_visibility(vLight, n);
  if (uMode == 0) {
    float fresnel = 0.02 + 0.98 * pow(1.0 - max(dot(n, v), 0.0), 5.0);
    vec3 deep = lit(vec3(0.05, 0.22, 0.33), n, vLight);
    vec3 r = reflect(-v, n);
    vec3 sky = sky_colour(vec3(r.xy, abs(r.z)));
    float glint = pow(max(dot(r, uSunDir), 0.0), 180.0) * sun;
    oColour = vec4(mix(deep, sky, fresnel) + vec3(glint), 0.88);
  } else {
    vec3 albedo = uMode == 1 ? lut(2.0, 0.5 + 0.5 * vDelta / uScale) : lut(0.0, 0.5 + 0.5 * vValue / uScale);
    oColour = vec4(lit(albedo, n, vLight), 0.95);
  }
}
)";

inline constexpr const char* kMeshVertex = R"(
layout(location = 0) in vec3 aPos;
layout(location = 1) in vec3 aNormal;
uniform mat4 uModel;
uniform mat4 uViewProj;
uniform mat4 uLightViewProj;
out vec3 vNormal;
out vec4 vLight;
void main() {
  vec4 w = uModel * vec4(aPos, 1.0);
  vNormal = mat3(uModel) * aNormal;
  vLight = uLightViewProj * w;
  gl_Position = uViewProj * w;
}
)";

inline constexpr const char* kMeshFragment = R"(
in vec3 vNormal;
in vec4 vLight;
out vec4 oColour;
uniform vec3 uColour;
void main() {
  vec3 n = normalize(vNormal);
  if (!gl_FrontFacing) n = -n;
  oColour = vec4(lit(uColour, n, vLight), 1.0);
}
)";

/// Depth only: the shadow map (the field and mesh vertex shaders write gl_Position from uViewProj).
inline constexpr const char* kDepthFragment = R"(
void main() {}
)";

inline constexpr const char* kSkyVertex = R"(
out vec2 vNdc;
void main() {
  vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
  vNdc = p;
  gl_Position = vec4(p, 1.0, 1.0);
}
)";

inline constexpr const char* kSkyFragment = R"(
in vec2 vNdc;
out vec4 oColour;
uniform mat4 uInvViewProj;
void main() {
  vec4 a = uInvViewProj * vec4(vNdc, -1.0, 1.0), b = uInvViewProj * vec4(vNdc, 1.0, 1.0);
  oColour = vec4(sky_colour(normalize(b.xyz / b.w - a.xyz / a.w)), 1.0);
}
)";

inline constexpr const char* kLineVertex = R"(
layout(location = 0) in vec3 aPos;
layout(location = 1) in vec3 aColour;
uniform mat4 uViewProj;
out vec3 vColour;
void main() {
  vColour = aColour;
  gl_Position = uViewProj * vec4(aPos, 1.0);
  gl_Position.z -= 0.0005 * gl_Position.w;  // over the surfaces they lie on
}
)";

inline constexpr const char* kLineFragment = R"(
in vec3 vColour;
out vec4 oColour;
void main() { oColour = vec4(vColour, 1.0); }
)";

}  // namespace shore::render::shaders
