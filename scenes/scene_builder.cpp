#include "scenes/scene.h"

#include "field/mesh_io.h"
#include "field/primitives.h"
#include "field/winding_number.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace rosy::scenes {

namespace {

field::Mesh makePrimitive(const MeshDesc &m) {
    const std::string &name = m.primitive->value;
    auto P = [&](const char *k) { return m.params.at(k).value; };
    auto I = [&](const char *k) { return int(std::lround(m.params.at(k).value)); };
    if (name == "icosphere") return field::makeIcosphere(I("subdivisions"), P("radius"));
    if (name == "ellipsoid") return field::makeEllipsoid(I("subdivisions"), P("a"), P("b"), P("c"));
    if (name == "torus") return field::makeTorus(P("major_radius"), P("minor_radius"), I("nu"), I("nv"));
    if (name == "genus2") return field::makeGenus2(I("resolution"));
    if (name == "cube") return field::makeCube(I("n"));
    if (name == "rounded_cube_pair") return field::makeRoundedCubePair(I("n"));
    if (name == "tetrahedron") return field::makePlatonic(field::Platonic::Tetrahedron, I("subdivisions"));
    if (name == "octahedron") return field::makePlatonic(field::Platonic::Octahedron, I("subdivisions"));
    if (name == "dodecahedron") return field::makePlatonic(field::Platonic::Dodecahedron, I("subdivisions"));
    if (name == "icosahedron") return field::makePlatonic(field::Platonic::Icosahedron, I("subdivisions"));
    if (name == "disk") return field::makeDisk(I("rings"));
    if (name == "grid") return field::makeGrid(I("n"));
    if (name == "cylinder")
        return field::makeCylinder(P("radius"), P("height"), I("n_around"), I("n_along"));
    ROSY_CHECK(!"primitive table and makePrimitive() disagree");
    return {};
}

/// Triangles of a Platonic solid before subdivision (pentagons as 5-fans).
long long platonicFaces(const std::string &name) {
    if (name == "tetrahedron") return 4;
    if (name == "octahedron") return 8;
    if (name == "dodecahedron") return 60;
    return 20; // icosahedron
}

/// The face limit of meshes (--max-faces) applies to primitives too: checked from
/// the parameters, before anything is allocated.
void checkPrimitiveFaces(const MeshDesc &m, const field::LoadOptions &options) {
    const long long faces = primitiveFaceCount(m);
    if (faces > options.maxFaces)
        throw InputError(m.primitive->loc,
                         "the " + m.primitive->value + " primitive would have " + std::to_string(faces) +
                             " faces, more than the limit of " + std::to_string(options.maxFaces),
                         "lower its resolution parameters, or raise the limit with --max-faces");
}

/// A manual camera must see some of the mesh and must not stand inside it. The
/// visibility test is conservative (the bounding sphere against the view
/// frustum), so it never rejects a camera that sees something.
void checkManualCamera(const renderer::Camera &cam, const field::Mesh &mesh, const CameraDesc &c) {
    Vec3 centre;
    double radius;
    renderer::boundingSphere(mesh, centre, radius);
    const Vec3 d = centre - cam.position();
    const double x = d.dot(cam.right()), y = d.dot(cam.up()), z = d.dot(cam.forward());
    const double aspect = double(cam.width()) / cam.height();
    bool outside;
    if (cam.projection() == renderer::Projection::Perspective) {
        const double ty = std::tan(0.5 * cam.fovYDeg() * M_PI / 180), tx = ty * aspect;
        // Signed distances of the centre outside each side plane through the eye.
        outside = z < -radius || (std::abs(x) - z * tx) / std::sqrt(1 + tx * tx) > radius ||
                  (std::abs(y) - z * ty) / std::sqrt(1 + ty * ty) > radius;
    } else {
        const double hy = 0.5 * cam.viewHeight(), hx = hy * aspect;
        outside = z < -radius || std::abs(x) > hx + radius || std::abs(y) > hy + radius;
    }
    const FileLoc &where = c.lookAt.loc.line ? c.lookAt.loc : c.loc;
    if (outside)
        throw InputError(where, "the camera sees none of the mesh (its bounding sphere, centre [" +
                                    fmt::format("{:g}", centre.x()) + ", " + fmt::format("{:g}", centre.y()) + ", " +
                                    fmt::format("{:g}", centre.z()) + "], radius " + fmt::format("{:g}", radius) +
                                    ", lies outside the view)",
                         "point look_at at the mesh, or use auto: true");
    if (std::abs(field::windingNumber(mesh, cam.position())) > 0.5)
        throw InputError(c.position.loc.line ? c.position.loc : c.loc,
                         "camera.position is inside the mesh, which hides its outside",
                         "move the camera outside the surface, or use auto: true");
}

} // namespace

Eigen::Matrix3d TransformDesc::linear() const {
    const Vec3 r = rotateDeg.value * (M_PI / 180.0);
    const Eigen::Matrix3d R = (Eigen::AngleAxisd(r.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(r.y(), Vec3::UnitY()) *
                               Eigen::AngleAxisd(r.x(), Vec3::UnitX()))
                                  .toRotationMatrix();
    return R * scale.value.asDiagonal();
}

field::Mesh transformMesh(const field::Mesh &mesh, const TransformDesc &transform) {
    const Eigen::Matrix3d L = transform.linear();
    std::vector<Vec3> positions(mesh.positions());
    for (Vec3 &q : positions) q = L * q + transform.translate.value;
    return field::Mesh::fromTriangles(std::move(positions), mesh.faces(), mesh.name());
}

long long primitiveFaceCount(const MeshDesc &m) {
    ROSY_CHECK(m.primitive.has_value());
    const std::string &name = m.primitive->value;
    auto I = [&](const char *k) { return (long long)std::llround(m.params.at(k).value); };
    auto pow4 = [](long long s) { return 1LL << (2 * s); };
    if (name == "icosphere" || name == "ellipsoid") return 20 * pow4(I("subdivisions"));
    if (name == "torus") return 2 * I("nu") * I("nv");
    if (name == "genus2") return field::genus2FaceCount(int(I("resolution")));
    if (name == "cube" || name == "rounded_cube_pair") return 12 * I("n") * I("n");
    if (name == "tetrahedron" || name == "octahedron" || name == "dodecahedron" || name == "icosahedron")
        return platonicFaces(name) * pow4(I("subdivisions"));
    if (name == "disk") return 6 * I("rings") * I("rings");
    if (name == "grid") return 2 * I("n") * I("n");
    if (name == "cylinder") return 2 * I("n_around") * I("n_along");
    ROSY_CHECK(!"primitive table and primitiveFaceCount() disagree");
    return 0;
}

uint64_t renderMemoryEstimate(double pixels, double faces, double minSpacingPx, bool exrOutput) {
    const double spacing = std::max(minSpacingPx, 0.5);
    const double perPixel = 130.0 + std::max(160.0 / spacing, exrOutput ? 100.0 : 0.0);
    const double perFace = 1300.0;
    return uint64_t(pixels * perPixel + faces * perFace);
}

uint64_t renderMemoryEstimate(const Scene &scene, bool exrOutput) {
    return renderMemoryEstimate(double(scene.camera.width()) * double(scene.camera.height()),
                                double(scene.mesh.nFaces()), scene.style.hatch.minSpacingPx, exrOutput);
}

Scene buildScene(const SceneDesc &desc, const field::LoadOptions &meshOptions) {
    Scene scene;
    if (!desc.mesh.file) checkPrimitiveFaces(desc.mesh, meshOptions);
    scene.mesh = desc.mesh.file ? field::loadMesh(desc.mesh.file->value, meshOptions) : makePrimitive(desc.mesh);
    if (scene.mesh.nFaces() == 0)
        throw InputError(desc.mesh.loc, "the mesh has no faces");
    // Before framing, so the automatic camera sees the transformed mesh.
    if (desc.mesh.transform.given) scene.mesh = transformMesh(scene.mesh, desc.mesh.transform);

    const CameraDesc &c = desc.camera;
    int w = c.resolution.value[0], h = c.resolution.value[1];
    if (c.automatic) {
        renderer::FramingOptions fo;
        fo.direction = c.direction.value;
        fo.up = c.up.value;
        fo.fovYDeg = c.fov.value;
        fo.margin = c.margin.value;
        fo.projection = c.projection.value;
        scene.camera = renderer::frameMesh(scene.mesh, w, h, fo);
    } else if (c.projection.value == renderer::Projection::Perspective) {
        scene.camera = renderer::Camera::perspective(c.position.value, c.lookAt.value, c.up.value,
                                                     c.fov.value, w, h);
    } else {
        scene.camera = renderer::Camera::orthographic(c.position.value, c.lookAt.value, c.up.value,
                                                      c.height.value, w, h);
    }
    if (!c.automatic) checkManualCamera(scene.camera, scene.mesh, c);

    if (desc.lightsGiven) {
        for (const LightDesc &l : desc.lights) scene.lights.push_back(l.light);
    } else {
        // A key light over the viewer's left shoulder: the classic illustration setup,
        // so form reads without the user placing a light.
        renderer::Light key;
        key.direction = (-0.6 * scene.camera.right() + 0.8 * scene.camera.up() -
                         0.7 * scene.camera.forward()).normalized();
        key.intensity = 1.0;
        scene.lights.push_back(key);
    }
    scene.shading.shadows = desc.shadows.value;
    scene.style = desc.style.style;
    scene.shading.ambient = scene.style.ambient;
    if (desc.ambientOcclusion.enabled && scene.mesh.nVertices() > 0) {
        Vec3 lo, hi;
        scene.mesh.bounds(lo, hi);
        // Relative to the mesh's size, so the drawing is the same at any scale.
        const double radius = desc.ambientOcclusion.radius * (hi - lo).norm();
        if (radius > 0.0) {
            scene.shading.aoSamples = desc.ambientOcclusion.samples;
            scene.shading.aoRadius = radius;
            scene.shading.aoSeed = scene.style.seed;
        }
    }
    scene.output = desc.output.value;
    return scene;
}

} // namespace rosy::scenes
