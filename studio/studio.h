#pragma once
/// \file studio.h
/// The state behind `rosyhatch studio`: one scene, one field, its design elements
/// and edits, undo/redo, previews and saving. Everything goes through the library:
/// the field is the pipeline's (scenes::buildSceneField on the scene text with the
/// current `field:` block), edits are field/edits.h's, previews are drawn by
/// scenes::drawHatching, the stage renderScene() ends with. The state is the scene
/// text itself: every change writes the `field:` block (scenes/scene_writer.h),
/// parses the text with the scene parser and builds from that, so a saved file
/// holds exactly what was shown and `rosyhatch render` of it draws the preview.
///
/// Thread-safe: every public call takes one mutex (previews a second one, so the
/// field can be edited while a preview is drawn), so concurrent requests see one
/// field and edits are applied one after the other.

#include "field/mesh_io.h"
#include "scenes/pipeline.h"
#include "scenes/scene_writer.h"
#include "studio/display_mesh.h"

#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace rosy::studio {

struct StudioOptions {
    field::LoadOptions load;
    /// Undo steps kept (each holds a copy of the field: 16 bytes per vertex).
    int undoLimit = 64;
    /// Largest preview side in pixels.
    int maxPreviewSide = 2048;
    /// Meshes with more faces than this are shown on the page as a display mesh of at
    /// most `displayFaces` faces (display_mesh.h); the field is still the full mesh's.
    int displayAbove = 100000;
    int displayFaces = 50000;
};

/// Binary layouts (little-endian; every section 4-byte aligned). Both describe the
/// display mesh (the scene's mesh itself up to StudioOptions::displayAbove faces):
///   mesh:  "RSM1", u32 nVertices, u32 nFaces, u32 decimated (0 or 1), f32[3 nV] positions,
///          u32[3 nF] corners, and when decimated u32[nV] the full mesh's vertex of each
///   field: "RSF1", u32 nVertices, u32 N, u32 0, f32[3 nV] first member direction
///          (unit, world; zero where the field vanishes), f32[3 nV] vertex normals, both
///          of the full mesh's vertex that each display vertex is
///   edit response: "RSE1", u32 jsonBytes (a multiple of 4, space-padded), the state
///          JSON (see stateJson()), then the field as above.
class Studio {
public:
    /// Reads and builds the scene (the file's `field:` block and edits included).
    /// \throws IoError / InputError as `rosyhatch render` would.
    explicit Studio(const std::string &scenePath, const StudioOptions &options = {});
    ~Studio();

    const std::string &scenePath() const { return m_path; }

    /// {scene, symmetry, source, smoothing_length, global_smoothing, elements [...],
    ///  edits [...], singularities [{id, face, position, index, index_numerator}],
    ///  index_sum, can_undo, can_redo, camera {...}, bounds {min, max}, vertices, faces}
    /// Also `display` {vertices, faces, decimated, cell_size}; each singularity and
    /// each element has `normal` (its face's on the full mesh).
    std::string stateJson() const;
    std::string meshBinary() const;
    std::string fieldBinary() const;
    /// Where a ray (from the page's camera through a clicked pixel) first meets the
    /// full mesh: {"hit": true, "position": [x,y,z], "face": F} or {"hit": false}.
    /// The page draws the display mesh; this puts a click on the true surface.
    /// \throws InputError for a zero or non-finite direction.
    std::string pick(const field::Vec3 &origin, const field::Vec3 &direction);
    /// pick() of a JSON body {"origin": [x,y,z], "direction": [x,y,z]}.
    std::string pick(const std::string &json);
    const DisplayMesh &displayMesh() const { return m_display; }
    bool decimated() const { return m_display.cellSize > 0.0; }
    /// {singularities: [...]} only.
    std::string singularitiesJson() const;
    /// {separatrices: [{singularity, incoming, points: [[x,y,z], ...]}]}
    std::string separatricesJson() const;

    /// Applies one edit given as JSON (the `op` key picks it; see docs/studio.md):
    /// add_element, update_element, delete_element, cancel, move_singularity,
    /// delete_edit, set. \returns the edit response (binary, see above).
    /// \throws InputError (state unchanged) for a malformed request or an edit the
    ///   library refuses, with its message.
    std::string edit(const std::string &json);
    std::string undo();
    std::string redo();
    /// The current field's hatching at `maxSide` pixels on the longer side (the scene
    /// camera's aspect kept), as the PNG `rosyhatch render` writes. With `original`,
    /// the field the scene file gave when the studio opened it (for a side-by-side
    /// original / edited comparison, as `rosyhatch compare --variants original,edited`).
    std::string previewPng(int maxSide, bool original = false);
    /// The preview's resolution for `maxSide` ([width, height]).
    std::array<int, 2> previewResolution(int maxSide) const;
    /// Writes the scene with the current `field:` block atomically: in place when
    /// `name` is empty or the scene's own file name, else as `name` (a plain file name
    /// ending in .yaml or .yml) beside the scene. \returns the path written.
    std::string save(const std::string &name);
    /// The scene text the current state would save.
    std::string sceneText() const;
    /// The current field (after the edits), as the pipeline built it, on the scene's own
    /// vertices (on a noisy scan carried back from the smoothed copy).
    field::RosyField field() const;
    /// Milliseconds per step of the last edit(), in order: parse (the scene text
    /// with the new `field:` block), the pipeline's field and singularities stages
    /// (on a noisy scan its scan_field, the field and singularities on the smoothed
    /// copy, after them or, once the scan was judged, instead of them),
    /// edits (applied again after a rebuild), singularities, directions, on a noisy
    /// scan carry_back (the field designed on its smoothed copy carried back to the
    /// scan's vertices), response.
    scenes::StageTimings lastEditTimings() const;

private:
    struct State;
    std::string editResponse() const;  ///< with m_mutex held
    std::string stateJsonLocked() const; ///< with m_mutex held
    /// Builds `state`'s field from its block (the pipeline, then its edits one by one).
    void rebuild(State &state) const;
    /// On a noisy scan, after the state's field on the copy changed: State::field
    /// carried back to the scene's vertices (timed as "carry_back").
    void carryBack(State &state) const;
    void push(State next);

    std::string m_path;
    std::string m_text; ///< the scene file as read
    StudioOptions m_options;
    scenes::LoadedScene m_loaded;
    /// What every field on the mesh shares (curvature, guide, Laplacian, snaps), kept
    /// across edits; the field is the same to the bit without it (field::FieldCache).
    std::unique_ptr<field::FieldCache> m_fieldCache;
    DisplayMesh m_display;
    std::string m_meshBytes;   ///< meshBinary(): the display mesh never changes
    std::string m_normalBytes; ///< the field response's constant half: f32 display vertex normals
    /// The same of a noisy scan's smoothed copy, whose tangent planes the directions
    /// then lie in (made by rebuild() the first time a state is designed on it).
    mutable std::string m_copyNormalBytes;
    /// A noisy scan's judgement that carries to fields differing only in their design
    /// elements (scenes::noiseJudgementCarries()): the `field:` block it was made for,
    /// as YAML without elements and edits, and the singularities judged. Set by
    /// rebuild(); an element added, moved or deleted then skips the field on the scan
    /// itself (scenes::PipelineOptions::judgedNoisy), any other change judges again.
    struct NoiseJudgement {
        std::string block;
        size_t singularities = 0;
    };
    mutable std::optional<NoiseJudgement> m_noiseJudgement;
    // pick(): the full mesh's ray scene, built on a thread at load for a decimated mesh
    // (else on the first pick).
    std::mutex m_pickMutex;
    std::future<std::unique_ptr<renderer::RayScene>> m_pickRaysBuilding;
    std::unique_ptr<renderer::RayScene> m_pickRays;
    std::unique_ptr<State> m_state;
    std::shared_ptr<const State> m_original; ///< the state the scene file gave
    std::vector<std::unique_ptr<State>> m_undo, m_redo;
    mutable std::mutex m_mutex;
    mutable scenes::StageTimings m_timings; ///< lastEditTimings(), with m_mutex held
    // Previews: the scene loaded at the preview's resolution and its ray scene.
    std::mutex m_previewMutex;
    std::array<int, 2> m_previewSize{0, 0};
    scenes::LoadedScene m_previewLoaded;
    std::unique_ptr<renderer::RayScene> m_previewRays;
};

} // namespace rosy::studio
