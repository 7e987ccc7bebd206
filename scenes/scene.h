#pragma once
/// \file scene.h
/// The scene file: YAML -> SceneDesc (plain data, every value tagged with where it
/// came from) -> Scene (loaded mesh, camera, lights). The format is documented in
/// scenes/README.md. Only this module sees yaml-cpp. The stages live in files of
/// their own, after pbrt-v4's seams:
///   yaml_reader.*    YAML with source locations, typed reads, size limits (internal)
///   overrides.*      --set KEY=VALUE and flag shorthands on the YAML tree (internal)
///   scene_parser.cpp YAML -> SceneDesc (parseScene, parseSceneFile)
///   style_presets.*  the `style:` block, its keys and the preset files
///   scene_builder.cpp SceneDesc -> Scene (buildScene: meshes, primitives, camera, lights)
///   suggest.*        "did you mean" for unknown names
///   pipeline.*       Scene -> field -> drawing (renderScene, buildSceneField)
///   compare.*        several fields of one scene side by side (compareScene)

#include "core/error.h"
#include "field/edits.h"
#include "field/field_builder.h"
#include "field/mesh.h"
#include "field/mesh_io.h"
#include "renderer/view/camera.h"
#include "renderer/view/shading.h"
#include "scenes/style_presets.h"
#include "scenes/suggest.h"
#include "styles/style.h"

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace rosy::scenes {

using Vec3 = Eigen::Vector3d;

/// A value and the place in the scene file it came from. loc.line == 0 means the
/// value is a default that the file did not set.
template <typename T>
struct Located {
    T value{};
    FileLoc loc;
};

/// `mesh.transform`: applied to the mesh right after loading, before framing and
/// before the field is built: p' = translate + Rz * Ry * Rx * (scale .* p), i.e.
/// scale first, then rotate about the world X, then Y, then Z axis (degrees,
/// counter-clockwise looking down the axis toward the origin), then translate.
struct TransformDesc {
    bool given = false;
    Located<Vec3> translate{Vec3::Zero(), {}};
    Located<Vec3> rotateDeg{Vec3::Zero(), {}};
    Located<Vec3> scale{Vec3::Ones(), {}}; ///< each > 0 (a number means all three)
    FileLoc loc;
    /// The linear part Rz * Ry * Rx * diag(scale).
    Eigen::Matrix3d linear() const;
    Vec3 apply(const Vec3 &p) const { return linear() * p + translate.value; }
};

/// Where the mesh comes from: a file or a procedural primitive.
struct MeshDesc {
    /// Path resolved against the scene file's folder (set when the mesh is a file).
    std::optional<Located<std::string>> file;
    /// Primitive name (icosphere, torus, ...), set when the mesh is procedural.
    std::optional<Located<std::string>> primitive;
    /// Every parameter of the primitive, defaults filled in (see README.md).
    std::map<std::string, Located<double>> params;
    /// Optional `transform:` (identity unless given).
    TransformDesc transform;
    FileLoc loc;
};

struct CameraDesc {
    /// True when the camera frames the mesh by itself (`auto: true` or no position).
    bool automatic = true;
    Located<renderer::Projection> projection{renderer::Projection::Perspective, {}};
    Located<Vec3> position;                          ///< manual only
    Located<Vec3> lookAt;                            ///< manual only
    Located<Vec3> up{Vec3(0, 1, 0), {}};
    Located<double> fov{35.0, {}};                   ///< vertical, degrees (perspective)
    Located<double> height{0.0, {}};                 ///< world image height (manual orthographic)
    Located<Vec3> direction{Vec3(1.0, 0.55, 1.6), {}}; ///< auto: from the object toward the camera
    Located<double> margin{0.1, {}};                 ///< auto: free space around the bounding sphere
    Located<std::array<int, 2>> resolution{{1024, 1024}, {}}; ///< width, height in pixels
    FileLoc loc;
};

struct LightDesc {
    renderer::Light light;
    FileLoc loc;
};

/// One topological edit of the field (P&Z Sec. 5.2), applied in file order; the
/// type lives in field/edits.h with the algorithm that applies it. Singularity ids
/// refer to the list as it is just before the edit (ids are re-numbered after
/// every edit, sorted by face id).
using FieldEditDesc = field::FieldEdit;

/// The scene's `field:` block: how to build the N-RoSy field and how to edit it.
struct FieldDesc {
    /// Whether the scene had a `field` key (otherwise `spec` holds the defaults).
    bool given = false;
    field::FieldSpec spec;
    /// Locations of the keys the file set (line 0: a default), so callers can tell
    /// a value the file chose from a default.
    FileLoc symmetryLoc, sourceLoc, smoothingLengthLoc;
    std::vector<FieldEditDesc> edits;
    FileLoc loc;
};

/// One applied edit, for reports (field/edits.h).
using AppliedEdit = field::AppliedEdit;
/// Applies a scene's (or a command line's) edits in order (field/edits.h).
using field::applyFieldEdits;

/// The scene's `style:` block resolved to one Style. Values come, lowest priority
/// first, from the Style defaults, the preset (if any) and the block's own keys.
struct StyleDesc {
    /// `preset:` as written (a preset name or a path to a YAML file), if given.
    std::optional<Located<std::string>> preset;
    /// The preset file that was read (empty without a preset).
    std::string presetPath;
    /// The resolved style.
    styles::Style style;
    /// Dotted key (e.g. "hatch.stroke_width_px") -> where its value was set: the
    /// preset file or the scene. Keys left at their defaults are absent.
    std::map<std::string, FileLoc> setAt;
    FileLoc loc;
};

/// What `rosyhatch render` draws: the pen-and-ink hatching (the default) or a
/// picture of the field itself (streamlines, singularity dots, separatrices) as in
/// the paper's Figures 2-5 (renderer/field_picture.h).
struct PictureDesc {
    enum class Kind { Hatching, Field };
    Located<Kind> kind{Kind::Hatching, {}};
    /// Field pictures: trace and draw each singularity's separatrices.
    Located<bool> separatrices{false, {}};
    FileLoc loc;
};

/// The top-level `ambient_occlusion` key (scenes/README.md).
struct AmbientOcclusionDesc {
    bool enabled = false;
    int samples = 16;    ///< occlusion rays per pixel, 1..1024
    double radius = 0.1; ///< ray length as a fraction of the mesh's bounding-box diagonal, (0, 10]
    FileLoc loc;
};

struct SceneDesc {
    /// The scene file as given (used in every message).
    std::string path;
    MeshDesc mesh;
    CameraDesc camera;
    /// Whether the file had a `lights` key; without it buildScene() adds a default key light.
    bool lightsGiven = false;
    std::vector<LightDesc> lights;
    Located<bool> shadows{true, {}};
    /// `ambient_occlusion`: off by default; `true` or a map {samples, radius} turns it on.
    AmbientOcclusionDesc ambientOcclusion;
    /// The `style:` block: defaults, then the preset, then inline overrides.
    StyleDesc style;
    /// The first output path (relative to the working directory, as given); default:
    /// the scene file's stem + ".png". Same as outputs.front().
    Located<std::string> output;
    /// Every output path (`output:` a path or a list of paths), all from one render;
    /// the format follows the extension (.png .exr .tif .tiff .jpg .jpeg .svg).
    std::vector<Located<std::string>> outputs;
    /// Top-level `threads` (0 = all cores); the CLI's --threads wins when given.
    Located<int> threads{0, {}};
    /// Top-level `seed`, if given. It sets style.style.seed unless the scene's
    /// `style:` block (or a --set style.seed) sets `seed` itself (a preset's seed
    /// does not count: the top-level seed overrides it).
    std::optional<Located<long long>> seed;
    /// The `field:` block (defaults when absent).
    FieldDesc field;
    /// The `picture:` block: what `rosyhatch render` draws.
    PictureDesc picture;
};

/// A command-line flag that is shorthand for one override: `rosyhatch render
/// --paper a3` is `--set style.page.size=a3`. Errors in its value are located at
/// the flag (`--paper: error: ...`).
struct FlagOverride {
    std::string flag;  ///< as typed, e.g. "--paper"
    std::string key;   ///< dotted scene key, e.g. "style.page.size"
    std::string value; ///< YAML text, e.g. "a3"
};

/// Reads and validates a scene file.
/// \param overrides  command-line overrides `dotted.key=VALUE` (`--set`), applied in
///   order to the YAML tree before validation; VALUE is YAML (`2`, `[512, 512]`,
///   `{preset: sketch}`), missing maps are created, list entries are addressed by
///   0-based position (`lights.0.intensity=0.5`). Errors in an overridden value are
///   located at the override: `--set field.symmetry=0: error: ...`.
/// \param flags  flag shorthands, applied after `overrides` (so a flag wins).
/// \throws IoError if the file cannot be read.
/// \throws InputError `FILE:LINE:COL: error: ...` for YAML syntax errors, unknown or
///   duplicate keys, wrong types, out-of-range values, a missing mesh file, a
///   malformed override.
SceneDesc parseSceneFile(const std::string &path, const std::vector<std::string> &overrides = {},
                         const std::vector<FlagOverride> &flags = {});

/// True for the mesh files the loader reads (.obj .ply .off .stl, any case).
bool isMeshPath(const std::string &path);

/// parseSceneFile() for a scene; for a mesh file (isMeshPath), the scene
/// `mesh: FILE` with every other key at its default (the automatic camera, the
/// default light and style, output FILE's stem + .png), so that `rosyhatch render
/// bunny.off` works and `--set` still applies.
SceneDesc parseSceneOrMesh(const std::string &path, const std::vector<std::string> &overrides = {},
                           const std::vector<FlagOverride> &flags = {});

/// Same as parseSceneFile() for text already in memory; `path` names it in messages
/// and relative mesh paths are resolved against its folder.
SceneDesc parseScene(const std::string &text, const std::string &path,
                     const std::vector<std::string> &overrides = {}, const std::vector<FlagOverride> &flags = {});

/// The objects a render needs.
struct Scene {
    field::Mesh mesh;
    renderer::Camera camera = renderer::Camera::perspective(Vec3(0, 0, 5), Vec3::Zero(),
                                                             Vec3(0, 1, 0), 35.0, 1, 1);
    std::vector<renderer::Light> lights;
    renderer::ShadingOptions shading;
    styles::Style style;
    std::string output;
};

/// Applies `transform` to every vertex of `mesh` (connectivity unchanged).
field::Mesh transformMesh(const field::Mesh &mesh, const TransformDesc &transform);

/// Loads the mesh (or builds the primitive), applies `mesh.transform`, makes the
/// camera (automatic framing sees the transformed mesh) and lights.
/// Without a `lights` key, one directional key light comes from the viewer's upper left.
/// \throws IoError / InputError from mesh loading; InputError at the camera's location
///   if the manual camera is degenerate for this mesh, sees none of it, or stands
///   inside a closed mesh. `meshOptions` carries the face limit (--max-faces), which
///   applies to mesh files and primitives alike.
Scene buildScene(const SceneDesc &desc, const field::LoadOptions &meshOptions = {});

/// The number of triangles the procedural mesh of `mesh` (mesh.primitive set) has,
/// computed from its parameters without building it. buildScene() refuses a
/// primitive with more faces than `meshOptions.maxFaces` (--max-faces, default
/// 20,000,000) before allocating it, at the `primitive:` value (InputError).
long long primitiveFaceCount(const MeshDesc &mesh);

/// Peak memory in bytes that rendering `scene` will add to what is allocated once
/// its mesh is loaded, from measurements of whole renders (README, "Limits";
/// peak RSS of bunny00 at 1024², 2048² and 4096²): per pixel 130 bytes of buffers
/// (G-buffer, screen field, ink layers) plus the larger of the hatching's strokes,
/// 160 / hatch.min_spacing_px bytes (427 bytes per pixel measured at the densest
/// 0.5 px), and an EXR output's channels, 100 bytes; per face 1300 bytes (frames,
/// field, solver, ray-tracing structure, contours: peak RSS at 1024² of a 270k-face
/// scan 302 MB, of the CGAL elephant subdivided to 5.7 M faces 4.89 GB and to 8.0 M
/// faces with noise 6.50 GB, about 820 bytes a face at that size; a scan judged noisy,
/// whose field is computed again on a smoothed copy (field/scan_noise.h), 2.80 GB at
/// 2.3 M faces and 10.3 GB at 9.1 M, 1.23 and 1.13 KB a face). Conservative: the
/// defaults measure 112 bytes per pixel (PNG) and 206 (EXR) against 180 and 230 estimated.
uint64_t renderMemoryEstimate(const Scene &scene, bool exrOutput);
/// The same from the numbers it depends on.
uint64_t renderMemoryEstimate(double pixels, double faces, double minSpacingPx, bool exrOutput);

/// Names the primitives a scene may use, for messages and documentation.
std::vector<std::string> primitiveNames();

} // namespace rosy::scenes
