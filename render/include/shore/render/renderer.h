#pragma once
// The OpenGL 3.3 renderer of Shore's scenes: the soils and the water surfaces as meshes
// simplified to a pixel bound for the frame's camera (shore::mesh, in chunks: only the
// chunks that changed are uploaded, those outside the view are not drawn), the water with
// normals and shading that make small waves visible, every Bullet body from its collision shape, one
// directional light with a shadow map, MSAA and a sky gradient; debug lines on top.
// The same renderer draws the viewer's window and the headless pictures (headless.h).
//
//   shore::render::Renderer r;            // a GL 3.3 core context must be current
//   r.set_contents(scene->contents());
//   r.draw(camera, 1280, 720, settings);  // after stepping: meshes brought up to date, then drawn
//   Image picture = r.read_image();       // or r.present(w, h) to the window

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "shore/render/camera.h"
#include "shore/render/line_batch.h"
#include "shore/scenes/contents.h"
#include "shore/scenes/image.h"

namespace shore::render {

enum class GroundColour {
  natural,      ///< the material's colour, lit
  deformation,  ///< height - untouched ground: blue lowered, red raised (the pictures' diverging map)
  sinkage,      ///< plastic sinkage: blue pressed, red loose soil laid on top
  height,       ///< hypsometric, low to high
};

enum class WaterColour {
  natural,   ///< deep water colour, sky reflection (Fresnel) and sun glints
  height,    ///< height - rest level: troughs deep blue, crests pale (the pictures' water map)
  velocity,  ///< vertical velocity: blue down, red up
};

struct RenderSettings {
  GroundColour ground = GroundColour::natural;
  double ground_scale = 0.0;  ///< m to full colour (deformation, sinkage); 0: the largest seen so far
  WaterColour water = WaterColour::natural;
  double water_scale = 0.0;        ///< m or m/s to full colour; 0: the largest now
  double wave_exaggeration = 0.0;  ///< water slopes are multiplied by this for shading, >= 1; 0: automatic
  bool soil_tile_borders = false;  ///< dark lines on the edges of the soils' storage tiles
  bool shadows = true;             ///< the sun's shadow map
  int samples = 4;                 ///< MSAA samples (1: none; at most what the GL allows)
  bool sky = true;                 ///< sky gradient behind (false: white)
  double max_error_pixels = 1.0;   ///< the soil and water meshes' projected error bound, pixels, > 0
  bool mesh_edges = false;         ///< outline the soil and water meshes' triangles (their level of detail)
  bool bodies = true;              ///< the world's bodies (false: soils and water alone)
  /// Natural ground colours (linear RGB in [0, 1]) by material name, over the defaults of
  /// material_colour(). A painted soil shows each column in its palette entry's colour.
  std::map<std::string, Eigen::Vector3d> material_colours;
};

/// A material's natural colour: settings.material_colours[name] if set, else the default of
/// its preset: sand (0.80, 0.70, 0.52), mud (0.45, 0.36, 0.27), snow (0.93, 0.94, 0.97),
/// rigid (0.60, 0.60, 0.60), gravel (0.56, 0.55, 0.52), dried mud (0.58, 0.49, 0.38); any other name sand's.
Eigen::Vector3d material_colour(const std::string& name, const RenderSettings& settings);

/// What the last draw() did.
struct FrameStats {
  std::int64_t soil_bytes = 0;         ///< soil mesh bytes (vertices and indices) uploaded for the last frame
  std::int64_t whole_soil_bytes = 0;   ///< uploading the drawn soils' full-resolution meshes once
  std::int64_t water_bytes = 0;        ///< water mesh bytes uploaded for the last frame
  std::int64_t whole_water_bytes = 0;  ///< uploading the water's full-resolution meshes once
  std::int64_t soil_columns = 0;       ///< drawn soil columns
  std::int64_t triangles = 0;          ///< triangles drawn in the colour pass (surfaces and bodies)
  std::int64_t surface_triangles = 0;  ///< of which soil and water
  std::int64_t full_triangles = 0;     ///< the soils' and water's full-resolution triangles (two per cell)
  int surface_chunks = 0;              ///< mesh chunks on the GPU
  int chunks_drawn = 0;                ///< in the colour pass
  int chunks_culled = 0;               ///< outside the view frustum, not drawn
  int bodies = 0;                      ///< collision objects drawn
  std::int64_t lines = 0;              ///< debug lines drawn
  double ground_scale = 0.0;           ///< the colour scale used (m)
  double water_scale = 0.0;            ///< the colour scale used (m or m/s)
};

class Renderer {
 public:
  /// Needs a current OpenGL 3.3 core context. Throws std::runtime_error if a shader fails.
  Renderer();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// Draws these contents from now on (drops the previous ones): the first draw uploads
  /// their meshes whole, later ones what changed (the soils' change generations, the
  /// water's moved nodes, the camera's move). The scene must outlive this renderer or the
  /// next set_contents()/clear().
  void set_contents(const scenes::SceneContents& contents);
  /// Forgets the contents.
  void clear();
  /// Brings the meshes up to date for the camera (uploading the changed chunks), then
  /// renders a width x height frame into the renderer's framebuffer.
  void draw(const OrbitCamera& camera, int width, int height, const RenderSettings& settings,
            const LineBatch* lines = nullptr);
  /// Copies the last frame to the current default framebuffer (a window).
  void present(int width, int height) const;
  /// The last frame as an RGB image, top row first.
  [[nodiscard]] scenes::Image read_image() const;

  /// The first point where a ray from `origin` along `direction` meets a soil or a water
  /// surface (or, failing those, the plane z = 0), if it meets one within 1 km.
  [[nodiscard]] std::optional<Eigen::Vector3d> pick(const Eigen::Vector3d& origin,
                                                    const Eigen::Vector3d& direction) const;
  [[nodiscard]] const FrameStats& stats() const noexcept;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace shore::render
