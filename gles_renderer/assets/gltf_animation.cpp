#include "gles_renderer/assets/gltf_animation.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace lumar {
namespace {

// glTF stores a quaternion as x, y, z, w; glm's constructor takes w first.
glm::quat loadQuat(const float* v)
{
    return glm::quat(v[3], v[0], v[1], v[2]);
}

void storeQuat(const glm::quat& q, std::span<float> out)
{
    out[0] = q.x;
    out[1] = q.y;
    out[2] = q.z;
    out[3] = q.w;
}

// A rotation made unit length (a zero one, which no keyframe should hold, as the identity).
glm::quat normalisedOrIdentity(const glm::quat& q)
{
    const float length = glm::length(q);
    return length > 1e-20f ? q / length : glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
}

} // namespace

glm::quat slerpShortest(const glm::quat& a, const glm::quat& b, float t)
{
    float d = glm::dot(a, b);
    glm::quat target = b;
    if (d < 0.0f) { // q and -q are the same rotation: take the shorter way round
        d = -d;
        target = -b;
    }
    if (d > 0.9995f) // nearly parallel: sin(theta) underflows, and a lerp is exact to float precision
        return normalisedOrIdentity(a + t * (target - a));
    const float theta = std::acos(std::min(d, 1.0f));
    const float s = std::sin(theta);
    return normalisedOrIdentity(a * (std::sin((1.0f - t) * theta) / s) + target * (std::sin(t * theta) / s));
}

void sampleAnimation(const AnimationSampler& sampler, float seconds, bool rotation, std::span<float> out)
{
    const size_t c = size_t(sampler.components);
    const size_t keys = sampler.times.size();
    const bool cubic = sampler.interpolation == Interpolation::CubicSpline;
    // Keyframe k's value: with CUBICSPLINE the middle of its (in-tangent, value, out-tangent).
    const auto value = [&](size_t k) { return sampler.values.data() + (cubic ? (3 * k + 1) * c : k * c); };
    const auto copyValue = [&](size_t k) {
        std::copy(value(k), value(k) + c, out.begin());
        if (rotation)
            storeQuat(normalisedOrIdentity(loadQuat(out.data())), out);
    };
    if (keys == 1 || !(seconds > sampler.times.front())) {
        copyValue(0);
        return;
    }
    if (seconds >= sampler.times.back()) {
        copyValue(keys - 1);
        return;
    }
    // The interval [times[k], times[k + 1]) holding `seconds`.
    const size_t k =
        size_t(std::upper_bound(sampler.times.begin(), sampler.times.end(), seconds) - sampler.times.begin()) - 1;
    const float t0 = sampler.times[k], t1 = sampler.times[k + 1];
    const float td = t1 - t0;
    const float s = (seconds - t0) / td;
    switch (sampler.interpolation) {
    case Interpolation::Step:
        copyValue(k);
        return;
    case Interpolation::Linear:
        if (rotation) {
            storeQuat(slerpShortest(loadQuat(value(k)), loadQuat(value(k + 1)), s), out);
        } else {
            const float* a = value(k);
            const float* b = value(k + 1);
            for (size_t i = 0; i < c; ++i)
                out[i] = a[i] + s * (b[i] - a[i]);
        }
        return;
    case Interpolation::CubicSpline: {
        // glTF 2.0 Appendix C: a Hermite spline through the values, the out-tangent of k and
        // the in-tangent of k + 1 scaled by the interval's length.
        const float s2 = s * s, s3 = s2 * s;
        const float h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
        const float* v0 = value(k);
        const float* outTangent0 = v0 + c;
        const float* v1 = value(k + 1);
        const float* inTangent1 = v1 - c;
        for (size_t i = 0; i < c; ++i)
            out[i] = h00 * v0[i] + h10 * td * outTangent0[i] + h01 * v1[i] + h11 * td * inTangent1[i];
        if (rotation)
            storeQuat(normalisedOrIdentity(loadQuat(out.data())), out);
        return;
    }
    }
}

double clipSeconds(double sceneSeconds, double duration, double speed, bool loop)
{
    const double t = sceneSeconds * speed;
    if (!(duration > 0.0) || !std::isfinite(t))
        return 0.0;
    if (!loop)
        return std::clamp(t, 0.0, duration);
    const double wrapped = std::fmod(t, duration);
    return wrapped < 0.0 ? wrapped + duration : wrapped;
}

} // namespace lumar
