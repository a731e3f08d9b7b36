// Shading numerics of the paper's model (mesh.frag with the real environment's maps) against
// formulas evaluated on the CPU: a plane facing the camera at its principal point (n.v = 1
// unless normal-mapped), read back at that pixel, within +-2 code values.
#include <array>
#include <cmath>
#include <numbers>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "gl_test_support.h"
#include "gles_renderer/assets/environment_map.h"

namespace lumar {
namespace {

constexpr int kWidth = 96;
constexpr int kHeight = 72;
constexpr int kTolerance = 2; // code values

// The plane's centre pixel: the principal point, where the view direction is the optical axis.
constexpr int kPx = 47, kPy = 35;

const CameraIntrinsics& intrinsics()
{
    static const CameraIntrinsics k = test::makeIntrinsics(kWidth, kHeight, 80, 80, kPx, kPy);
    return k;
}

GltfMaterial surface(float metallic, float roughness)
{
    GltfMaterial m;
    m.baseColorFactor = glm::vec4(1.0f);
    m.metallicFactor = metallic;
    m.roughnessFactor = roughness;
    return m;
}

// The colour at the principal point of a plane facing the camera 1 m ahead.
glm::ivec3 planeColour(SceneRenderer& renderer, const GltfModel& plane)
{
    renderer.removeModels();
    const DrawItem item{renderer.addModel(plane), test::translation(0, 0, 1)};
    Image8 out;
    renderer.render(test::solidImage(kWidth, kHeight, 0, 0, 0), intrinsics(), {&item, 1});
    renderer.readback(out);
    const uint8_t* p = out.at(kPx, kPy);
    return {p[0], p[1], p[2]};
}

GltfModel plane(const GltfMaterial& material)
{
    return test::cameraFacingRectangle(-0.2f, -0.2f, 0.2f, 0.2f, material);
}

void expectColour(const glm::ivec3& actual, const glm::dvec3& radiance)
{
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(actual[c], test::toneMappedCode(radiance[c]), kTolerance)
            << "channel " << c << ", radiance " << radiance[c];
}

// An equirectangular map of radiance(direction), directions per environment_map.h.
template <typename F> ImageF equirectOf(int width, int height, F radiance)
{
    ImageF map(width, height, 3);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const double theta = (y + 0.5) / height * std::numbers::pi;
            const double phi = ((x + 0.5) / width - 0.5) * 2.0 * std::numbers::pi;
            const glm::dvec3 l =
                radiance(glm::dvec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)));
            for (int c = 0; c < 3; ++c)
                map.at(x, y)[c] = float(l[c]);
        }
    return map;
}

// Narrow lobes (red: near the zenith, green: between +x and +y, blue: between +y and +z)
// carry strong band-1 and band-2 terms, so every SH coefficient shows in the diffuse term.
glm::dvec3 lobedSky(const glm::dvec3& d)
{
    const auto lobe = [&](double x, double y, double z) {
        return 1.5 * std::pow(std::max(0.0, glm::dot(d, glm::normalize(glm::dvec3(x, y, z)))), 4.0);
    };
    return glm::dvec3(0.05) + glm::dvec3(lobe(1, 2, 1), lobe(1, 1, 0), lobe(0, 1, 1));
}

// The diffuse map's value E(n)/pi from the CPU's SH9 of the equirectangular map.
glm::dvec3 diffuseMapValue(const ImageF& sky, const glm::dvec3& direction)
{
    return glm::dvec3(irradianceSH9(projectEquirectSH9(sky), glm::vec3(direction))) / std::numbers::pi;
}

// A white dielectric at roughness 1 under the paper's model: rho_d = 1, rho_s = 0.04, the
// exponent clamps to 1 (glossiness 0: the diffuse map) and phi = 1/6. The lobe peak is the
// mirror direction r; at n.v = cos the Fresnel factor (1 - cos)^5 raises rho_s, the falloff
// and the glossiness (the last shifts weight 4f towards the n = 8 map, which the planes
// here, with cos >= 0.8, make a < 1e-4 change, far below a code value).
glm::dvec3 roughWhiteRadiance(const ImageF& sky, const glm::dvec3& normalInEnvironment,
                              const glm::dvec3& mirrorInEnvironment, double nDotV)
{
    const double f = std::pow(1.0 - nDotV, 5.0);
    const double rhoS = 0.04 + 0.96 * f;
    const double falloff = nDotV + (1.0 - nDotV) * f;
    return diffuseMapValue(sky, normalInEnvironment) + rhoS * falloff * diffuseMapValue(sky, mirrorInEnvironment);
}

// White Lambertian plus the 4% dielectric lobe: under uniform radiance L every map holds L,
// so at n = v (no Fresnel gain) the plane shows (rho_d + rho_s) L = 1.04 L.
TEST(Shading, WhiteDiffusePlaneUnderUniformLightIsToneMappedRadiance)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    for (const auto& [radiance, intensity] : {std::pair{0.05f, 1.0f}, {0.3f, 1.0f}, {0.6f, 1.0f}, {0.5f, 3.0f}}) {
        SCOPED_TRACE(testing::Message() << "L = " << radiance << " x " << intensity);
        renderer.setEnvironment(test::uniformEnvironment(radiance), intensity);
        const double l = double(radiance) * intensity;
        expectColour(planeColour(renderer, plane(surface(0.0f, 1.0f))), glm::dvec3(l * 1.04));
    }
}

// A smooth white metal is a mirror: rho_s = 1 at the mirror map shows the radiance itself.
TEST(Shading, SmoothMetalReflectsTheUniformEnvironment)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    for (const float radiance : {0.2f, 0.8f}) {
        renderer.setEnvironment(test::uniformEnvironment(radiance), 1.0f);
        expectColour(planeColour(renderer, plane(surface(1.0f, 0.0f))), glm::dvec3(radiance));
    }
}

// sRGB base-colour texels are decoded to linear before shading: a texel of code 188 is an
// albedo of srgbDecode(188/255) ~ 0.50, not 0.74.
TEST(Shading, BaseColourTextureIsDecodedFromSrgb)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    const float radiance = 0.7f;
    renderer.setEnvironment(test::uniformEnvironment(radiance), 1.0f);
    GltfModel model = plane(surface(0.0f, 1.0f));
    GltfTexture texture;
    texture.image = Image8(4, 4, 4);
    for (size_t i = 0; i < texture.image.data.size(); i += 4) {
        texture.image.data[i] = 188;
        texture.image.data[i + 1] = 100;
        texture.image.data[i + 2] = 30;
        texture.image.data[i + 3] = 255;
    }
    texture.srgb = true;
    model.textures.push_back(texture);
    model.materials[0].baseColorTexture = 0;
    const glm::dvec3 albedo(test::srgbDecode(188 / 255.0), test::srgbDecode(100 / 255.0), test::srgbDecode(30 / 255.0));
    expectColour(planeColour(renderer, model), double(radiance) * (albedo + 0.04));
}

// A direction-dependent, coloured environment: the diffuse term follows the CPU's SH9
// irradiance at the plane's normal turned into the environment frame, for several
// environment rotations.
TEST(Shading, DiffuseIrradianceFollowsTheEnvironmentAndItsRotation)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    const ImageF sky = equirectOf(256, 128, lobedSky);
    renderer.setEnvironment(sky, 1.0f);
    const glm::dvec3 normalInCamera(0, 0, -1);
    const glm::dmat4 identity(1.0);
    const glm::dmat3 rotations[] = {
        glm::dmat3(1.0),
        glm::dmat3(glm::rotate(identity, glm::radians(-90.0), glm::dvec3(1, 0, 0))), // faces up (+y)
        glm::dmat3(glm::rotate(identity, glm::radians(90.0), glm::dvec3(0, 1, 0))),  // faces +x
        glm::dmat3(glm::rotate(identity, glm::radians(135.0), glm::dvec3(1, 0, 0))), // faces +y+z
        glm::dmat3(glm::rotate(identity, glm::radians(70.0), glm::normalize(glm::dvec3(1, 2, 0.5)))),
    };
    for (const glm::dmat3& environmentFromCamera : rotations) {
        const glm::dvec3 n = environmentFromCamera * normalInCamera;
        SCOPED_TRACE(testing::Message() << "normal in the environment (" << n.x << ", " << n.y << ", " << n.z << ")");
        renderer.setEnvironmentRotation(environmentFromCamera);
        expectColour(planeColour(renderer, plane(surface(0.0f, 1.0f))), roughWhiteRadiance(sky, n, n, 1.0));
    }
}

// A tangent-space normal map turns the shading normal: n = normalize(T x + B y + N z) with
// (x, y) scaled by normalScale and B = (N x T) * handedness (glTF), here T = camera +x,
// B = camera -y (image up), N = camera -z.
TEST(Shading, NormalMapTurnsTheShadingNormal)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    const ImageF sky = equirectOf(256, 128, lobedSky);
    renderer.setEnvironment(sky, 1.0f);
    const glm::dmat3 environmentFromCamera(glm::rotate(glm::dmat4(1.0), glm::radians(-60.0), glm::dvec3(1, 0, 0)));
    renderer.setEnvironmentRotation(environmentFromCamera);

    const uint8_t texel[3] = {200, 90, 220};
    const float normalScale = 0.8f;
    GltfModel model = plane(surface(0.0f, 1.0f));
    GltfTexture normalMap{Image8(4, 4, 4), false};
    for (size_t i = 0; i < normalMap.image.data.size(); i += 4) {
        std::copy(texel, texel + 3, normalMap.image.data.begin() + long(i));
        normalMap.image.data[i + 3] = 255;
    }
    model.textures.push_back(normalMap);
    model.materials[0].normalTexture = 0;
    model.materials[0].normalScale = normalScale;

    glm::dvec3 tangentNormal = glm::dvec3(texel[0], texel[1], texel[2]) / 255.0 * 2.0 - 1.0;
    tangentNormal.x *= normalScale;
    tangentNormal.y *= normalScale;
    const glm::dvec3 t(1, 0, 0), b(0, -1, 0), n(0, 0, -1);
    const glm::dvec3 shadingNormal = glm::normalize(t * tangentNormal.x + b * tangentNormal.y + n * tangentNormal.z);
    const glm::dvec3 view(0, 0, -1); // towards the camera
    const auto mirror = [&](const glm::dvec3& normal) { return 2.0 * glm::dot(view, normal) * normal - view; };
    expectColour(planeColour(renderer, model),
                 roughWhiteRadiance(sky, environmentFromCamera * shadingNormal,
                                    environmentFromCamera * mirror(shadingNormal), glm::dot(shadingNormal, view)));

    // Mirrored uvs (handedness -1) turn B around.
    for (glm::vec4& tangent : model.primitives[0].tangents)
        tangent.w = -1.0f;
    const glm::dvec3 mirroredNormal = glm::normalize(t * tangentNormal.x - b * tangentNormal.y + n * tangentNormal.z);
    expectColour(planeColour(renderer, model),
                 roughWhiteRadiance(sky, environmentFromCamera * mirroredNormal,
                                    environmentFromCamera * mirror(mirroredNormal), glm::dot(mirroredNormal, view)));
}

// A normal map with a KHR_texture_transform: its texels' x and y axes are where the
// transformed uv' grows on the surface (x: +u', y: -v', glTF's convention), found here by the
// chain rule from uv' = A uv (T = dP/du, B = -dP/dv): dP/du' and dP/dv' are the columns of
// (T, -B) A^-1, made unit length.
TEST(Shading, NormalMapTextureTransformTurnsTheTangentFrame)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    const ImageF sky = equirectOf(256, 128, lobedSky);
    renderer.setEnvironment(sky, 1.0f);
    const glm::dmat3 environmentFromCamera(glm::rotate(glm::dmat4(1.0), glm::radians(-60.0), glm::dvec3(1, 0, 0)));
    renderer.setEnvironmentRotation(environmentFromCamera);

    const uint8_t texel[3] = {200, 90, 220};
    GltfModel model = plane(surface(0.0f, 1.0f));
    GltfTexture normalMap{Image8(4, 4, 4), false};
    for (size_t i = 0; i < normalMap.image.data.size(); i += 4) {
        std::copy(texel, texel + 3, normalMap.image.data.begin() + long(i));
        normalMap.image.data[i + 3] = 255;
    }
    model.textures.push_back(normalMap);
    model.materials[0].normalTexture = 0;
    const glm::dvec3 tangentNormal = glm::dvec3(texel[0], texel[1], texel[2]) / 255.0 * 2.0 - 1.0;
    const glm::dvec3 t(1, 0, 0), b(0, -1, 0), n(0, 0, -1);
    const glm::dvec3 view(0, 0, -1);
    const auto mirror = [&](const glm::dvec3& normal) { return 2.0 * glm::dot(view, normal) * normal - view; };
    for (const auto& [degrees, scale] : {std::pair{90.0f, glm::vec2(1.0f)},
                                         {30.0f, glm::vec2(2.0f)},
                                         {-135.0f, glm::vec2(1.0f)},
                                         {90.0f, glm::vec2(-1.0f, 1.0f)}}) {
        SCOPED_TRACE(testing::Message() << "rotation " << degrees << " deg, scale (" << scale.x << ", " << scale.y
                                        << ")");
        GltfUvTransform& transform = model.materials[0].uvTransforms[size_t(GltfTextureSlot::Normal)];
        transform.rotation = glm::radians(degrees);
        transform.scale = scale;
        const std::array<glm::vec3, 2> rows = transform.rows();
        const glm::dmat2 a(rows[0].x, rows[1].x, rows[0].y, rows[1].y); // columns
        const glm::dmat2 inverse = glm::inverse(a);
        const glm::dvec3 alongU = glm::normalize(t * inverse[0][0] - b * inverse[0][1]);  // dP/du'
        const glm::dvec3 alongV = -glm::normalize(t * inverse[1][0] - b * inverse[1][1]); // -dP/dv'
        const glm::dvec3 shadingNormal =
            glm::normalize(alongU * tangentNormal.x + alongV * tangentNormal.y + n * tangentNormal.z);
        expectColour(planeColour(renderer, model),
                     roughWhiteRadiance(sky, environmentFromCamera * shadingNormal,
                                        environmentFromCamera * mirror(shadingNormal), glm::dot(shadingNormal, view)));
    }
}

// A ridge in a normal map (its left half tilted to the image's left, its right half to the
// right), turned 90 degrees by KHR_texture_transform, runs across the plane: under a sky
// bright above (the camera's -y), the ridge's upper half faces the light and is brighter.
// Read without turning the tangent frame, both halves would lean sideways and match.
TEST(Shading, RotatedNormalMapRidgeIsLitOnTheSideFacingTheLight)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    renderer.setEnvironment(equirectOf(256, 128, [](const glm::dvec3& d) { return glm::dvec3(0.3 - 0.25 * d.y); }),
                            1.0f);
    renderer.setEnvironmentRotation(glm::dmat3(1.0));
    GltfModel model = plane(surface(0.0f, 1.0f));
    GltfTexture ridge{Image8(4, 4, 4), false};
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            uint8_t* p = ridge.image.at(x, y);
            p[0] = x < 2 ? 51 : 204; // tangent x = -0.6 | +0.6
            p[1] = 128;
            p[2] = 230; // z = 0.8
            p[3] = 255;
        }
    model.textures.push_back(ridge);
    model.materials[0].normalTexture = 0;
    model.materials[0].uvTransforms[size_t(GltfTextureSlot::Normal)].rotation = glm::radians(90.0f);
    // uv' = (v, -u): the plane's upper half (v = 1/4) reads u' = 1/4, the ridge's left half.
    renderer.removeModels();
    const DrawItem item{renderer.addModel(model), test::translation(0, 0, 1)};
    Image8 out;
    renderer.render(test::solidImage(kWidth, kHeight, 0, 0, 0), intrinsics(), {&item, 1});
    renderer.readback(out);
    const auto luma = [&](int x, int y) {
        const uint8_t* p = out.at(x, y);
        return int(p[0]) + int(p[1]) + int(p[2]);
    };
    const int upper = luma(kPx, kPy - 8), lower = luma(kPx, kPy + 8);
    EXPECT_GT(upper, lower + 3 * 20) << "the ridge's upper half faces the bright sky above";
    // Along the ridge the two sides of the plane are alike.
    EXPECT_NEAR(luma(kPx - 8, kPy - 8), luma(kPx + 8, kPy - 8), 3 * 3);
}

// A smooth metal plane facing the camera mirrors the view ray straight back: at the principal
// point it shows the environment's radiance in direction environmentFromCamera * (0, 0, -1),
// looked up in the equirectangular map with environment_map.h's convention. The map is a
// smooth function of direction (linear in d), so bilinear lookups match it to ~1e-3 except
// at the poles, where the nearest texel row is half a row away: 0.25 sin(pi / 256) ~ 0.003.
TEST(Shading, SmoothMetalMirrorsTheEnvironmentAlongTheReflection)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    const auto radianceTowards = [](const glm::dvec3& d) { return glm::dvec3(0.3) + 0.25 * d; };
    const ImageF map = equirectOf(256, 128, radianceTowards);
    renderer.setEnvironment(map, 1.0f);
    const glm::dvec3 reflectedInCamera(0, 0, -1);
    // Towards +x, -x (the map's u seam), +z, up, down and an oblique direction.
    const glm::dmat4 identity(1.0);
    const glm::dmat3 rotations[] = {
        glm::dmat3(glm::rotate(identity, glm::radians(-90.0), glm::dvec3(0, 1, 0))),
        glm::dmat3(glm::rotate(identity, glm::radians(90.0), glm::dvec3(0, 1, 0))),
        glm::dmat3(glm::rotate(identity, glm::radians(180.0), glm::dvec3(0, 1, 0))),
        glm::dmat3(glm::rotate(identity, glm::radians(-90.0), glm::dvec3(1, 0, 0))),
        glm::dmat3(glm::rotate(identity, glm::radians(90.0), glm::dvec3(1, 0, 0))),
        glm::dmat3(glm::rotate(identity, glm::radians(130.0), glm::normalize(glm::dvec3(-1, 3, 2)))),
    };
    for (const glm::dmat3& environmentFromCamera : rotations) {
        const glm::dvec3 d = environmentFromCamera * reflectedInCamera;
        SCOPED_TRACE(testing::Message() << "reflected towards (" << d.x << ", " << d.y << ", " << d.z << ")");
        renderer.setEnvironmentRotation(environmentFromCamera);
        expectColour(planeColour(renderer, plane(surface(1.0f, 0.0f))), radianceTowards(d));
    }
}

// Emission adds to reflected light.
TEST(Shading, EmissionAddsToReflectedLight)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    renderer.setEnvironment(test::uniformEnvironment(0.2f), 1.0f);
    GltfMaterial m = surface(0.0f, 1.0f);
    m.baseColorFactor = glm::vec4(0.5f, 0.5f, 0.5f, 1.0f);
    m.emissiveFactor = glm::vec3(0.3f, 0.0f, 0.9f);
    const double reflected = 0.2 * (0.5 + 0.04);
    expectColour(planeColour(renderer, plane(m)), glm::dvec3(reflected) + glm::dvec3(0.3, 0.0, 0.9));
}

} // namespace
} // namespace lumar
