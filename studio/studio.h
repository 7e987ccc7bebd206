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

#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace rosy::studio {

struct StudioOptions {
    field::LoadOptions load;
    /// Undo steps kept (each holds a copy of the field: 16 bytes per vertex).
    int undoLimit = 64;
    /// Largest preview side in pixels.
    int maxPreviewSide = 2048;
};

/// Binary layouts (little-endian; every section 4-byte aligned):
///   mesh:  "RSM1", u32 nVertices, u32 nFaces, u32 0, f32[3 nV] positions, u32[3 nF] corners
///   field: "RSF1", u32 nVertices, u32 N, u32 0, f32[3 nV] first member direction
///          (unit, world; zero where the field vanishes), f32[3 nV] vertex normals
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
    std::string stateJson() const;
    std::string meshBinary() const;
    std::string fieldBinary() const;
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
    /// camera's aspect kept), as the PNG `rosyhatch render` writes.
    std::string previewPng(int maxSide);
    /// The preview's resolution for `maxSide` ([width, height]).
    std::array<int, 2> previewResolution(int maxSide) const;
    /// Writes the scene with the current `field:` block atomically: in place when
    /// `name` is empty or the scene's own file name, else as `name` (a plain file name
    /// ending in .yaml or .yml) beside the scene. \returns the path written.
    std::string save(const std::string &name);
    /// The scene text the current state would save.
    std::string sceneText() const;

private:
    struct State;
    std::string editResponse() const;  ///< with m_mutex held
    std::string stateJsonLocked() const; ///< with m_mutex held
    /// Builds `state`'s field from its block (the pipeline, then its edits one by one).
    void rebuild(State &state) const;
    void push(State next);

    std::string m_path;
    std::string m_text; ///< the scene file as read
    StudioOptions m_options;
    scenes::LoadedScene m_loaded;
    std::string m_normalBytes; ///< the field response's constant half: f32 vertex normals
    std::unique_ptr<State> m_state;
    std::vector<std::unique_ptr<State>> m_undo, m_redo;
    mutable std::mutex m_mutex;
    // Previews: the scene loaded at the preview's resolution and its ray scene.
    std::mutex m_previewMutex;
    std::array<int, 2> m_previewSize{0, 0};
    scenes::LoadedScene m_previewLoaded;
    std::unique_ptr<renderer::RayScene> m_previewRays;
};

} // namespace rosy::studio
