/// \file studio.cpp
/// The studio's state and its edits (studio.h).

#include "studio/studio.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/input_file.h"
#include "core/parallel.h"
#include "field/design.h"
#include "field/singularities.h"
#include "renderer/output/image.h"
#include "renderer/view/embree_scene.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <future>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>

namespace rosy::studio {

using nlohmann::json;
using field::Vec3;

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

constexpr size_t kMaxSceneBytes = 4u << 20; // as the scene parser (README, "Limits")
constexpr size_t kMaxElements = 1000, kMaxEdits = 1000;

const FileLoc kRequest{"request"};

[[noreturn]] void bad(const std::string &what, const std::string &fix) { throw InputError(kRequest, what, fix); }

double number(const json &j, const char *key) {
    auto it = j.find(key);
    if (it == j.end() || !it->is_number()) bad(std::string("`") + key + "` must be a number", "send it as a JSON number");
    const double x = it->get<double>();
    if (!std::isfinite(x)) bad(std::string("`") + key + "` must be finite", "send a finite number");
    return x;
}

int integer(const json &j, const char *key) {
    auto it = j.find(key);
    if (it == j.end() || !it->is_number_integer())
        bad(std::string("`") + key + "` must be an integer", "send it as a JSON integer");
    const long long v = it->get<long long>();
    if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
        bad(std::string("`") + key + "` is out of range", "send a smaller integer");
    return int(v);
}

Vec3 vec3(const json &j, const char *key) {
    auto it = j.find(key);
    if (it == j.end() || !it->is_array() || it->size() != 3)
        bad(std::string("`") + key + "` must be a list of three numbers", "e.g. [0, 1, 0]");
    Vec3 v;
    for (int i = 0; i < 3; ++i) {
        if (!(*it)[i].is_number()) bad(std::string("`") + key + "` must be a list of three numbers", "e.g. [0, 1, 0]");
        v[i] = (*it)[i].get<double>();
        if (!std::isfinite(v[i])) bad(std::string("`") + key + "` must be finite", "send finite numbers");
    }
    return v;
}

void onlyKeys(const json &j, std::initializer_list<const char *> keys) {
    for (auto it = j.begin(); it != j.end(); ++it) {
        bool known = false;
        std::string list;
        for (const char *k : keys) {
            known = known || it.key() == k;
            list += std::string(list.empty() ? "" : ", ") + k;
        }
        if (!known) bad("unknown key `" + it.key() + "` for op `" + j.value("op", "") + "`", "use only: " + list);
    }
}

json vecJson(const Vec3 &v) { return json::array({v.x(), v.y(), v.z()}); }

void putU32(std::string &out, uint32_t v) { out.append(reinterpret_cast<const char *>(&v), 4); }
void putF32(std::string &out, double v) {
    const float f = float(v);
    out.append(reinterpret_cast<const char *>(&f), 4);
}

std::string normalBytes(const field::TangentFrames &frames, const std::vector<int> &shown); // below
void updateDirections(const field::TangentFrames &frames, const std::vector<int> &shown, const field::RosyField &f,
                      std::vector<float> &dirs, const field::RosyField *previous); // below
std::string meshBytes(const field::Mesh &mesh, const DisplayMesh &display); // below

int elementIndex(const json &j, size_t count) {
    const int i = integer(j, "index");
    if (i < 0 || size_t(i) >= count)
        bad("element " + std::to_string(i) + " does not exist (there are " + std::to_string(count) + ")",
            "use an index from the element list");
    return i;
}

} // namespace

/// One state of the design: the scene's `field:` block and the field it gives.
struct Studio::State {
    /// The frames the field is designed on: the copy's on a noisy scan, else `own`.
    const field::TangentFrames &designFrames(const field::TangentFrames &own) const {
        return copy ? *copy->frames : own;
    }
    field::RosyField &designField() { return copy ? fieldOnCopy : field; }
    const field::RosyField &designField() const { return copy ? fieldOnCopy : field; }
    /// The singularities of designField(), placed on the scene's surface (`own`'s mesh).
    field::SingularityReport findSingularities(const field::TangentFrames &own) const {
        field::SingularityReport r = field::findSingularities(designFrames(own), designField());
        return copy ? field::placedOn(std::move(r), own.mesh()) : r;
    }
    scenes::FieldBlock block;
    /// Per edit: where its singularity was when the edit was made (moves made in the
    /// studio; NaN otherwise). After the field below changes, a move is re-aimed at
    /// the first-order singularity nearest to this point, as ids are renumbered.
    std::vector<Vec3> moveFrom;
    /// On the scene's own vertices (on a noisy scan: carried back from the copy, as
    /// scenes::SceneFieldResult::field).
    field::RosyField field;
    /// A noisy scan (field/scan_noise.h): the smoothed copy the field is designed on,
    /// as the pipeline does (the loaded scene's, shared by all states), and the field
    /// on its frames. Edits, singularities, separatrices, the shown directions and
    /// the preview's tone and screen field are then the copy's. Null: the surface's own.
    std::shared_ptr<const field::SmoothedSurface> copy;
    field::RosyField fieldOnCopy;
    /// Placed on the scene's surface (on a scan: the copy's, field::placedOn()).
    field::SingularityReport singularities;
    /// Per element: the unit normal of the face it snaps to (the page turns
    /// directions about it).
    std::vector<Vec3> elementNormals;
    /// f32 first member direction per display vertex (the field response's first half).
    std::vector<float> directions;
};

Studio::Studio(const std::string &scenePath, const StudioOptions &options) : m_path(scenePath), m_options(options) {
    m_text = readInputFile(scenePath, InputFileRules{"scene file", kMaxSceneBytes, false});
    const scenes::SceneDesc desc = scenes::parseScene(m_text, m_path);
    scenes::PipelineOptions po;
    po.load = options.load;
    m_loaded = scenes::loadScene(desc, po);
    m_fieldCache = std::make_unique<field::FieldCache>(*m_loaded.frames);
    const field::Mesh &mesh = m_loaded.scene->mesh;
    m_display = makeDisplayMesh(mesh, mesh.nFaces() > options.displayAbove ? options.displayFaces : mesh.nFaces());
    if (decimated()) // picks on the display mesh go to the full surface: its rays, ready early
        m_pickRaysBuilding = std::async(std::launch::async, [&mesh] { return std::make_unique<renderer::RayScene>(mesh); });
    m_meshBytes = meshBytes(mesh, m_display);
    m_normalBytes = normalBytes(*m_loaded.frames, m_display.fullVertex);
    auto state = std::make_unique<State>();
    state->block = scenes::fieldBlockOf(desc.field.spec, desc.field.edits);
    state->moveFrom.assign(state->block.edits.size(), Vec3::Constant(std::nan("")));
    rebuild(*state);
    m_original = std::make_shared<const State>(*state);
    m_state = std::move(state);
}

Studio::~Studio() = default;

void Studio::rebuild(State &s) const {
    if (s.block.elements.size() > kMaxElements) bad("too many design elements", "at most 1000");
    if (s.block.edits.size() > kMaxEdits) bad("too many edits", "at most 1000");
    auto t0 = Clock::now();
    const scenes::SceneDesc desc = scenes::parseScene(scenes::replaceFieldBlock(m_text, m_path, s.block), m_path);
    m_timings.emplace_back("parse", msSince(t0));
    scenes::PipelineOptions po;
    po.load = m_options.load;
    po.applyEdits = false; // applied one by one below, moves re-aimed first
    po.fieldCache = m_fieldCache.get();
    scenes::FieldBlock judged = s.block; // what the judgement depends on
    judged.elements.clear();
    judged.edits.clear();
    const std::string judgedBlock = scenes::fieldBlockYaml(judged);
    if (m_noiseJudgement && m_noiseJudgement->block == judgedBlock) po.judgedNoisy = m_noiseJudgement->singularities;
    scenes::SceneFieldResult r = scenes::buildSceneField(m_loaded, desc.field, po, &m_timings);
    if (!po.judgedNoisy && scenes::noiseJudgementCarries(r))
        m_noiseJudgement = NoiseJudgement{judgedBlock, r.noisySingularities};
    const bool sameFrames = r.smoothedSurface == s.copy; // the previous field's directions can be kept
    s.copy = r.smoothedSurface;
    const field::TangentFrames &frames = s.designFrames(*m_loaded.frames);
    field::RosyField f = std::move(s.copy ? r.smoothedField : r.field.field);
    if (s.copy && m_copyNormalBytes.empty()) m_copyNormalBytes = normalBytes(frames, m_display.fullVertex);
    t0 = Clock::now();
    for (size_t i = 0; i < s.block.edits.size(); ++i) {
        field::FieldEdit e = desc.field.edits[i];
        if (e.op == field::FieldEdit::Op::Move && std::isfinite(s.moveFrom[i].x())) {
            const auto sings = field::findSingularities(frames, f).singularities;
            int best = -1;
            double bestD = std::numeric_limits<double>::infinity();
            for (size_t k = 0; k < sings.size(); ++k) {
                if (std::abs(sings[k].indexNumerator) != 1) continue;
                const double d = (sings[k].position - s.moveFrom[i]).norm();
                if (d < bestD) bestD = d, best = int(k);
            }
            if (best < 0)
                bad("edit " + std::to_string(i) + " (move) has no first-order singularity left to move",
                    "delete the edit or undo");
            e.a = s.block.edits[i].a = best;
        }
        try {
            field::applyFieldEdits(frames, f, {e});
        } catch (const InputError &err) {
            bad("edit " + std::to_string(i) + " (" + field::toString(e.op) + ") no longer applies to the changed field: " +
                    err.what(),
                "delete that edit (or undo) first");
        }
    }
    m_timings.emplace_back("edits", msSince(t0));
    t0 = Clock::now();
    // The field kept (the previous one for the directions below).
    const field::RosyField previous = std::move(s.designField());
    s.designField() = std::move(f);
    if (!s.copy) s.fieldOnCopy = {};
    // Without edits the pipeline's singularities are those of this very field.
    s.singularities = s.block.edits.empty() ? std::move(r.singularities) : s.findSingularities(*m_loaded.frames);
    s.elementNormals.clear();
    const std::vector<field::SnappedElement> snaps = m_fieldCache->snapped(desc.field.spec.elements); // as the field's
    for (size_t k = 0; k < snaps.size(); ++k) // direction elements only
        s.elementNormals.push_back(desc.field.spec.elements[k].order == 0 && snaps[k].face >= 0
                                       ? frames.mesh().faceNormal(snaps[k].face)
                                       : Vec3::Zero());
    m_timings.emplace_back("singularities", msSince(t0));
    t0 = Clock::now();
    // Directions: only where the field changed from the state `s` was copied from.
    updateDirections(frames, m_display.fullVertex, s.designField(), s.directions,
                     sameFrames && previous.u.size() == s.designField().u.size() ? &previous : nullptr);
    m_timings.emplace_back("directions", msSince(t0));
    carryBack(s);
}

void Studio::carryBack(State &s) const {
    if (!s.copy) return;
    const auto t0 = Clock::now();
    s.field = field::carryField(*s.copy->frames, s.fieldOnCopy, *m_loaded.frames);
    m_timings.emplace_back("carry_back", msSince(t0));
}

void Studio::push(State next) {
    m_undo.push_back(std::move(m_state));
    if (int(m_undo.size()) > m_options.undoLimit) m_undo.erase(m_undo.begin());
    m_redo.clear();
    m_state = std::make_unique<State>(std::move(next));
}

std::string Studio::edit(const std::string &body) {
    json j;
    try {
        j = json::parse(body);
    } catch (const json::exception &e) {
        bad(std::string("the body is not JSON: ") + e.what(), "send a JSON object such as {\"op\": \"undo\"}");
    }
    if (!j.is_object() || !j.contains("op") || !j["op"].is_string())
        bad("the body must be a JSON object with a string `op`",
            "ops: add_element, update_element, delete_element, cancel, move_singularity, delete_edit, set");
    const std::string op = j["op"];
    std::lock_guard lock(m_mutex);
    m_timings.clear();
    State next = *m_state;
    const field::TangentFrames &frames = next.designFrames(*m_loaded.frames);
    const auto &sings = m_state->singularities.singularities;
    auto singularity = [&](const char *key) {
        const int id = integer(j, key);
        if (id < 0 || size_t(id) >= sings.size())
            bad("singularity " + std::to_string(id) + " does not exist (there are " + std::to_string(sings.size()) + ")",
                "use an id from the singularity list");
        return id;
    };
    auto readElement = [&](scenes::FieldBlock::Element &el, bool partial) {
        if (!partial || j.contains("position")) el.position = vec3(j, "position");
        if (!partial || j.contains("order")) el.order = integer(j, "order");
        if (el.order < -1 || el.order > 1) bad("`order` must be -1, 0 or 1", "0: regular, ±1: singular");
        if (j.contains("direction")) el.direction = vec3(j, "direction");
        if (j.contains("phase")) el.phaseDeg = number(j, "phase");
        if (j.contains("strength")) el.strength = number(j, "strength");
    };
    bool incremental = false;
    if (op == "add_element") {
        onlyKeys(j, {"op", "position", "order", "direction", "phase", "strength"});
        scenes::FieldBlock::Element el;
        readElement(el, false);
        next.block.elements.push_back(el);
    } else if (op == "update_element") {
        onlyKeys(j, {"op", "index", "position", "order", "direction", "phase", "strength"});
        readElement(next.block.elements[elementIndex(j, next.block.elements.size())], true);
    } else if (op == "delete_element") {
        onlyKeys(j, {"op", "index"});
        next.block.elements.erase(next.block.elements.begin() + elementIndex(j, next.block.elements.size()));
        if (next.block.elements.empty() && next.block.source == field::FieldSource::Design)
            bad("a designed field needs at least one element", "add another element first, or set the source");
    } else if (op == "cancel") {
        onlyKeys(j, {"op", "a", "b"});
        const int a = singularity("a"), b = singularity("b");
        if (a == b) bad("a singularity cannot cancel itself", "pick two singularities");
        if (sings[a].indexNumerator * sings[b].indexNumerator != -1)
            bad("singularities " + std::to_string(a) + " and " + std::to_string(b) + " have indices " +
                    std::to_string(sings[a].indexNumerator) + "/N and " + std::to_string(sings[b].indexNumerator) +
                    "/N; only a +1/N and a -1/N pair cancels",
                "pick one positive and one negative first-order singularity");
        field::FieldEdit e;
        e.op = field::FieldEdit::Op::CancelNear; // positions, so the edit survives renumbering
        e.p = sings[a].position;
        e.q = sings[b].position;
        next.block.edits.push_back(e);
        next.moveFrom.push_back(Vec3::Constant(std::nan("")));
        incremental = true;
    } else if (op == "move_singularity") {
        onlyKeys(j, {"op", "id", "to"});
        field::FieldEdit e;
        e.op = field::FieldEdit::Op::Move;
        e.a = singularity("id");
        e.p = vec3(j, "to");
        next.block.edits.push_back(e);
        next.moveFrom.push_back(sings[e.a].position);
        incremental = true;
    } else if (op == "delete_edit") {
        onlyKeys(j, {"op", "index"});
        const int i = integer(j, "index");
        if (i < 0 || size_t(i) >= next.block.edits.size())
            bad("edit " + std::to_string(i) + " does not exist", "use an index from the edit list");
        next.block.edits.erase(next.block.edits.begin() + i);
        next.moveFrom.erase(next.moveFrom.begin() + i);
    } else if (op == "set") {
        onlyKeys(j, {"op", "symmetry", "source", "smoothing_length", "global_smoothing_iterations",
                     "global_smoothing_strength", "weights"});
        if (j.contains("symmetry")) next.block.symmetry = integer(j, "symmetry");
        if (j.contains("source")) {
            if (!j["source"].is_string()) bad("`source` must be a string", "curvature, smoothest or design");
            const std::string s = j["source"];
            if (s == "curvature") next.block.source = field::FieldSource::Curvature;
            else if (s == "smoothest") next.block.source = field::FieldSource::Smoothest;
            else if (s == "design") next.block.source = field::FieldSource::Design;
            else bad("unknown source `" + s + "`", "curvature, smoothest or design");
        }
        if (j.contains("weights")) {
            if (!j["weights"].is_string()) bad("`weights` must be a string", "meanvalue or cotan");
            const std::string s = j["weights"];
            if (s == "meanvalue") next.block.weights = field::LaplaceWeights::MeanValue;
            else if (s == "cotan") next.block.weights = field::LaplaceWeights::Cotan;
            else bad("unknown weights `" + s + "`", "meanvalue or cotan");
        }
        if (j.contains("smoothing_length")) next.block.smoothingLength = number(j, "smoothing_length");
        if (j.contains("global_smoothing_iterations"))
            next.block.globalSmoothingIterations = integer(j, "global_smoothing_iterations");
        if (j.contains("global_smoothing_strength"))
            next.block.globalSmoothingStrength = number(j, "global_smoothing_strength");
    } else {
        bad("unknown op `" + op + "`",
            "ops: add_element, update_element, delete_element, cancel, move_singularity, delete_edit, set");
    }
    if (incremental) {
        if (next.block.edits.size() > kMaxEdits) bad("too many edits", "at most 1000");
        // The same as rebuild() would do: the new edit applied to the current field.
        auto t0 = Clock::now();
        field::applyFieldEdits(frames, next.designField(), {next.block.edits.back()});
        m_timings.emplace_back("edits", msSince(t0));
        t0 = Clock::now();
        next.singularities = next.findSingularities(*m_loaded.frames);
        m_timings.emplace_back("singularities", msSince(t0));
        t0 = Clock::now();
        updateDirections(frames, m_display.fullVertex, next.designField(), next.directions, &m_state->designField());
        m_timings.emplace_back("directions", msSince(t0));
        carryBack(next);
    } else {
        rebuild(next);
    }
    push(std::move(next));
    const auto t0 = Clock::now();
    std::string response = editResponse();
    m_timings.emplace_back("response", msSince(t0));
    return response;
}

field::RosyField Studio::field() const {
    std::lock_guard lock(m_mutex);
    return m_state->field;
}

scenes::StageTimings Studio::lastEditTimings() const {
    std::lock_guard lock(m_mutex);
    return m_timings;
}

std::string Studio::undo() {
    std::lock_guard lock(m_mutex);
    if (m_undo.empty()) bad("nothing to undo", "make an edit first");
    m_redo.push_back(std::move(m_state));
    m_state = std::move(m_undo.back());
    m_undo.pop_back();
    return editResponse();
}

std::string Studio::redo() {
    std::lock_guard lock(m_mutex);
    if (m_redo.empty()) bad("nothing to redo", "undo an edit first");
    m_undo.push_back(std::move(m_state));
    m_state = std::move(m_redo.back());
    m_redo.pop_back();
    return editResponse();
}

namespace {

json singularityList(const field::Mesh &mesh, const std::vector<field::Singularity> &sings) {
    json list = json::array();
    for (size_t i = 0; i < sings.size(); ++i) {
        const field::Singularity &s = sings[i];
        list.push_back({{"id", int(i)},
                        {"face", s.face},
                        {"position", vecJson(s.position)},
                        {"normal", vecJson(s.face >= 0 ? mesh.faceNormal(s.face) : Vec3::Zero())},
                        {"index", s.index()},
                        {"index_numerator", s.indexNumerator}});
    }
    return list;
}

/// Unit world direction of the first member at each shown vertex (`shown[i]` the
/// full mesh's vertex of display vertex i; zero where the field vanishes). With
/// `previous` (the field the directions were computed for), only the vertices whose
/// representation vector changed are recomputed: an edit changes a small region and
/// leaves the rest bit for bit (field/editing.h).
void updateDirections(const field::TangentFrames &frames, const std::vector<int> &shown, const field::RosyField &f,
                      std::vector<float> &dirs, const field::RosyField *previous) {
    const int64_t nShown = int64_t(shown.size());
    const bool all = !previous || previous->nSym != f.nSym || dirs.size() != 3 * size_t(nShown);
    if (all) dirs.assign(3 * size_t(nShown), 0.0f);
    parallelFor(0, nShown, [&](int64_t i) {
        const int v = shown[i];
        if (!all && f.u[v] == previous->u[v]) return;
        Vec3 d = Vec3::Zero();
        if (std::abs(f.u[v]) > 1e-12) d = frames.tangentOfAngle(v, field::memberAngle(f.u[v], f.nSym)).normalized();
        for (int c = 0; c < 3; ++c) dirs[3 * i + c] = float(d[c]);
    });
}

/// The field's binary form; `normals` is the constant second half (f32 normals).
std::string fieldBytes(const field::RosyField &f, const std::vector<float> &dirs, const std::string &normals) {
    std::string out;
    out.reserve(16 + dirs.size() * sizeof(float) + normals.size());
    out += "RSF1";
    putU32(out, uint32_t(dirs.size() / 3));
    putU32(out, uint32_t(f.nSym));
    putU32(out, 0);
    out.append(reinterpret_cast<const char *>(dirs.data()), dirs.size() * sizeof(float));
    out += normals;
    return out;
}

std::string normalBytes(const field::TangentFrames &frames, const std::vector<int> &shown) {
    std::string out;
    out.reserve(12 * shown.size());
    for (int v : shown)
        for (int c = 0; c < 3; ++c) putF32(out, frames.normal(v)[c]);
    return out;
}

std::string meshBytes(const field::Mesh &mesh, const DisplayMesh &display) {
    const bool decimated = display.cellSize > 0.0;
    const size_t nV = display.fullVertex.size(), nF = display.faces.size();
    std::string out;
    out.reserve(16 + 12 * nV + 12 * nF + (decimated ? 4 * nV : 0));
    out += "RSM1";
    putU32(out, uint32_t(nV));
    putU32(out, uint32_t(nF));
    putU32(out, decimated ? 1 : 0);
    for (int v : display.fullVertex)
        for (int c = 0; c < 3; ++c) putF32(out, mesh.position(v)[c]);
    for (const field::Face &f : display.faces)
        for (int c = 0; c < 3; ++c) putU32(out, uint32_t(f[c]));
    if (decimated)
        for (int v : display.fullVertex) putU32(out, uint32_t(v));
    return out;
}

} // namespace

std::string Studio::stateJson() const {
    std::lock_guard lock(m_mutex);
    return stateJsonLocked();
}

std::string Studio::stateJsonLocked() const {
    const State &s = *m_state;
    const scenes::Scene &scene = *m_loaded.scene;
    json j;
    j["scene"] = m_path;
    j["symmetry"] = s.block.symmetry;
    j["source"] = field::toString(s.block.source);
    j["smoothing_length"] = s.block.smoothingLength;
    j["weights"] = s.block.weights == field::LaplaceWeights::Cotan ? "cotan" : "meanvalue";
    j["global_smoothing"] = {{"iterations", s.block.globalSmoothingIterations},
                             {"strength", s.block.globalSmoothingStrength}};
    json elements = json::array();
    for (size_t i = 0; i < s.block.elements.size(); ++i) {
        const auto &e = s.block.elements[i];
        json el = {{"position", vecJson(e.position)}, {"order", e.order}, {"strength", e.strength}};
        if (e.order == 0 && i < s.elementNormals.size()) el["normal"] = vecJson(s.elementNormals[i]);
        if (e.order == 0) el["direction"] = vecJson(e.direction);
        else el["phase"] = e.phaseDeg;
        elements.push_back(el);
    }
    j["elements"] = elements;
    json edits = json::array();
    for (const auto &e : s.block.edits) {
        json ed = {{"op", field::toString(e.op)}};
        if (e.op == field::FieldEdit::Op::Cancel) ed["ids"] = {e.a, e.b};
        if (e.op == field::FieldEdit::Op::Move) ed["id"] = e.a, ed["to"] = vecJson(e.p);
        if (e.op == field::FieldEdit::Op::CancelNear) ed["points"] = {vecJson(e.p), vecJson(e.q)};
        edits.push_back(ed);
    }
    j["edits"] = edits;
    j["singularities"] = singularityList(scene.mesh, s.singularities.singularities);
    j["index_sum"] = double(s.singularities.indexNumeratorSum) / s.block.symmetry;
    j["boundary_index"] = s.singularities.boundaryIndex;
    j["can_undo"] = !m_undo.empty();
    j["can_redo"] = !m_redo.empty();
    const renderer::Camera &cam = scene.camera;
    j["camera"] = {{"position", vecJson(cam.position())},
                   {"forward", vecJson(cam.forward())},
                   {"up", vecJson(cam.up())},
                   {"fov", cam.fovYDeg()},
                   {"orthographic", cam.projection() == renderer::Projection::Orthographic},
                   {"view_height", cam.viewHeight()},
                   {"width", cam.width()},
                   {"height", cam.height()}};
    Vec3 lo, hi;
    scene.mesh.bounds(lo, hi);
    j["bounds"] = {{"min", vecJson(lo)}, {"max", vecJson(hi)}};
    j["vertices"] = scene.mesh.nVertices();
    j["faces"] = scene.mesh.nFaces();
    j["display"] = {{"vertices", m_display.fullVertex.size()},
                    {"faces", m_display.faces.size()},
                    {"decimated", decimated()},
                    {"cell_size", m_display.cellSize}};
    return j.dump();
}

std::string Studio::editResponse() const {
    std::string state = stateJsonLocked(); // m_mutex is held
    while (state.size() % 4) state += ' ';
    std::string out = "RSE1";
    putU32(out, uint32_t(state.size()));
    out += state;
    out += fieldBytes(m_state->field, m_state->directions, m_state->copy ? m_copyNormalBytes : m_normalBytes);
    return out;
}

std::string Studio::meshBinary() const { return m_meshBytes; }

std::string Studio::pick(const std::string &body) {
    json j;
    try {
        j = json::parse(body);
    } catch (const json::exception &e) {
        bad(std::string("the body is not JSON: ") + e.what(), "send {\"origin\": [x,y,z], \"direction\": [x,y,z]}");
    }
    if (!j.is_object()) bad("the body must be a JSON object", "send {\"origin\": [x,y,z], \"direction\": [x,y,z]}");
    onlyKeys(j, {"origin", "direction"});
    return pick(vec3(j, "origin"), vec3(j, "direction"));
}

std::string Studio::pick(const Vec3 &origin, const Vec3 &direction) {
    if (!origin.allFinite() || !direction.allFinite() || direction.norm() < 1e-30)
        bad("a pick needs a finite origin and a non-zero finite direction", "send origin [x,y,z], direction [x,y,z]");
    std::lock_guard lock(m_pickMutex);
    if (!m_pickRays) {
        if (m_pickRaysBuilding.valid()) m_pickRays = m_pickRaysBuilding.get();
        else m_pickRays = std::make_unique<renderer::RayScene>(m_loaded.scene->mesh);
    }
    renderer::Ray ray;
    ray.origin = origin;
    ray.dir = direction.normalized();
    const renderer::Hit hit = m_pickRays->intersect(ray);
    if (!hit.valid()) return json{{"hit", false}}.dump();
    // The point from the barycentrics, in double precision, on the full mesh's face.
    const field::Mesh &mesh = m_loaded.scene->mesh;
    const field::Face &f = mesh.face(hit.faceId);
    const Vec3 p = (1.0 - hit.u - hit.v) * mesh.position(f[0]) + hit.u * mesh.position(f[1]) + hit.v * mesh.position(f[2]);
    return json{{"hit", true}, {"position", vecJson(p)}, {"face", hit.faceId}}.dump();
}

std::string Studio::fieldBinary() const {
    std::lock_guard lock(m_mutex);
    return fieldBytes(m_state->field, m_state->directions, m_state->copy ? m_copyNormalBytes : m_normalBytes);
}

std::string Studio::singularitiesJson() const {
    std::lock_guard lock(m_mutex);
    return json{{"singularities", singularityList(m_loaded.scene->mesh, m_state->singularities.singularities)}}.dump();
}

std::string Studio::separatricesJson() const {
    std::lock_guard lock(m_mutex);
    // On a noisy scan they lie on the smoothed copy the field is designed on.
    const auto seps = field::traceSeparatrices(m_state->designFrames(*m_loaded.frames), m_state->designField(),
                                               m_state->singularities.singularities);
    json list = json::array();
    for (const field::Separatrix &s : seps) {
        json pts = json::array();
        for (const Vec3 &p : s.line.points) pts.push_back(vecJson(p));
        list.push_back({{"singularity", s.singularity}, {"incoming", s.incoming}, {"points", pts}});
    }
    return json{{"separatrices", list}}.dump();
}

std::array<int, 2> Studio::previewResolution(int maxSide) const {
    if (maxSide < 16 || maxSide > m_options.maxPreviewSide)
        bad("preview size " + std::to_string(maxSide) + " is out of range",
            "ask for 16 to " + std::to_string(m_options.maxPreviewSide) + " pixels");
    const renderer::Camera &cam = m_loaded.scene->camera;
    const double scale = double(maxSide) / std::max(cam.width(), cam.height());
    return {std::max(1, int(std::lround(cam.width() * scale))), std::max(1, int(std::lround(cam.height() * scale)))};
}

std::string Studio::sceneText() const {
    std::lock_guard lock(m_mutex);
    return scenes::replaceFieldBlock(m_text, m_path, m_state->block);
}

std::string Studio::previewPng(int maxSide, bool original) {
    const std::array<int, 2> size = previewResolution(maxSide);
    field::RosyField f, fOnCopy;
    field::SingularityReport sings;
    std::shared_ptr<const field::SmoothedSurface> copy;
    {
        std::lock_guard lock(m_mutex);
        const State &s = original ? *m_original : *m_state;
        f = s.field;
        sings = s.singularities;
        copy = s.copy;
        fOnCopy = s.fieldOnCopy;
    }
    std::lock_guard lock(m_previewMutex);
    if (size != m_previewSize) {
        // The scene as `render --set camera.resolution=[w,h]` reads it.
        const scenes::SceneDesc desc = scenes::parseScene(
            m_text, m_path, {"camera.resolution=[" + std::to_string(size[0]) + "," + std::to_string(size[1]) + "]"});
        if (desc.picture.kind.value != scenes::PictureDesc::Kind::Hatching)
            bad("the preview draws the hatching, and this scene is a field picture (picture.kind: field)",
                "the field is on the page already; render the scene for its picture");
        m_previewRays.reset();
        scenes::PipelineOptions po;
        po.load = m_options.load;
        m_previewLoaded = scenes::loadScene(desc, po);
        m_previewRays = std::make_unique<renderer::RayScene>(m_previewLoaded.scene->mesh);
        m_previewSize = size;
    }
    // On a noisy scan, shaded and projected from the copy as `render` does (the
    // preview's scene is the same file, so the same vertices and faces).
    std::optional<scenes::FieldOnCopy> onCopy;
    if (copy) onCopy.emplace(scenes::FieldOnCopy{*copy, fOnCopy});
    const renderer::Illustration il = scenes::drawHatching(m_previewLoaded, f, sings, *m_previewRays,
                                                           renderer::HatchMeasure::None, true, onCopy ? &*onCopy : nullptr);
    // The PNG exactly as `render -o x.png` writes it: through writeImage, into a
    // private temporary folder, read back.
    std::string dirTemplate = (std::filesystem::temp_directory_path() / "rosyhatch-studio-XXXXXX").string();
    if (!mkdtemp(dirTemplate.data())) 
        throw IoError(dirTemplate, std::string("cannot create a temporary folder: ") + std::strerror(errno));
    const std::filesystem::path file = std::filesystem::path(dirTemplate) / "preview.png";
    std::string bytes;
    try {
        renderer::writeImage(il.composite, file.string());
        std::ifstream in(file, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
    } catch (...) {
        std::error_code ec;
        std::filesystem::remove_all(dirTemplate, ec);
        throw;
    }
    std::error_code ec;
    std::filesystem::remove_all(dirTemplate, ec);
    return bytes;
}

std::string Studio::save(const std::string &name) {
    namespace fs = std::filesystem;
    const fs::path scene(m_path);
    fs::path target = scene;
    if (!name.empty() && name != scene.filename().string()) {
        bool ok = name.size() <= 200 && name[0] != '.';
        for (char c : name) ok = ok && (std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-');
        const std::string ext = fs::path(name).extension().string();
        if (!ok || (ext != ".yaml" && ext != ".yml"))
            bad("cannot save as `" + name + "`: the name must be a plain file name ending in .yaml",
                "e.g. bunny-edited.yaml (it is written beside the scene)");
        target = scene.parent_path() / name;
    }
    const std::string text = sceneText();
    // The text must read back as a scene (it always should: it is what the field was built from).
    const scenes::SceneDesc desc = scenes::parseScene(text, target.string());
    if (!desc.style.presetPath.empty()) checkNotAnInput(target.string(), desc.style.presetPath, "style preset");
    if (desc.mesh.file) checkNotAnInput(target.string(), desc.mesh.file->value, "input mesh");
    writeTextAtomically(target.string(), text);
    return target.string();
}

} // namespace rosy::studio
