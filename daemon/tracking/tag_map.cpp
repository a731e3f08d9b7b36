// solveMapPose: one pose for a multi-tag map from all its detected tags' corners
// (tag_map.h).
#include "tracking/tag_map.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "core/log.h"

namespace lumar {
namespace {

// The per-tag bound (tag_pose.cpp): beyond it the corners do not fit the map's layout (a
// tag moved on the board, a layout measured wrong, a false detection with a map's id).
constexpr double kMaxMapRmsPx = 4.0;

cv::Matx33d toCv(const glm::dmat3& m)
{
    cv::Matx33d r;
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col)
            r(row, col) = m[col][row];
    return r;
}

glm::dmat3 toGlm(const cv::Matx33d& m)
{
    glm::dmat3 r;
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col)
            r[col][row] = m(row, col);
    return r;
}

struct Correspondences {
    std::vector<glm::dvec3> mapPoints;
    std::vector<cv::Point2d> imagePoints;
};

double reprojectionRms(const Pose& cameraFromMap, const Correspondences& c, const cv::Matx33d& cameraMatrix,
                       const std::vector<double>& distortion)
{
    std::vector<cv::Point3d> points;
    points.reserve(c.mapPoints.size());
    for (const glm::dvec3& p : c.mapPoints) {
        const glm::dvec3 q = cameraFromMap.apply(p);
        if (!(q.z > 0.0))
            return std::numeric_limits<double>::infinity();
        points.emplace_back(q.x, q.y, q.z);
    }
    std::vector<cv::Point2d> projected;
    cv::projectPoints(points, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), cameraMatrix, distortion, projected);
    double sum = 0.0;
    for (size_t i = 0; i < projected.size(); ++i) {
        const cv::Point2d d = projected[i] - c.imagePoints[i];
        sum += d.dot(d);
    }
    return std::sqrt(sum / double(projected.size()));
}

bool finite(const Pose& p)
{
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            if (!std::isfinite(p.R[c][r]))
                return false;
    return std::isfinite(p.t.x) && std::isfinite(p.t.y) && std::isfinite(p.t.z);
}

} // namespace

TagMap makeTagMap(const MapConfig& config)
{
    TagMap map;
    map.name = config.name;
    for (const MapTagConfig& tag : config.tags) {
        glm::dmat4 m(1.0);
        m = glm::rotate(m, glm::radians(tag.rotationDeg.z), glm::dvec3(0, 0, 1));
        m = glm::rotate(m, glm::radians(tag.rotationDeg.y), glm::dvec3(0, 1, 0));
        m = glm::rotate(m, glm::radians(tag.rotationDeg.x), glm::dvec3(1, 0, 0));
        map.tags.push_back({tag.id, tag.size, Pose{glm::dmat3(m), tag.position}});
    }
    return map;
}

bool solveMapPose(const TagMap& map, const std::vector<TagDetection>& detections, const CameraIntrinsics& intrinsics,
                  MapDetection& out)
{
    Correspondences c;
    std::vector<Pose> candidates; // each usable tag's pose carried into the map frame
    std::vector<int> ids;
    for (const TagMapTag& tag : map.tags) {
        const TagDetection* found = nullptr;
        int seen = 0;
        for (const TagDetection& d : detections)
            if (d.id == tag.id) {
                found = &d;
                ++seen;
            }
        // A tag without a plausible pose of its own, or seen twice, is not trusted.
        if (seen != 1 || !found->hasPose)
            continue;
        const auto corners = tagCornersInMarkerFrame(tag.size);
        for (size_t i = 0; i < 4; ++i) {
            c.mapPoints.push_back(tag.mapFromTag.apply(corners[i]));
            c.imagePoints.emplace_back(found->corners[i].x, found->corners[i].y);
        }
        candidates.push_back(found->cameraFromMarker * tag.mapFromTag.inverse());
        ids.push_back(tag.id);
    }
    if (candidates.empty())
        return false;

    const cv::Matx33d cameraMatrix(intrinsics.fx, 0.0, intrinsics.cx, 0.0, intrinsics.fy, intrinsics.cy, 0.0, 0.0, 1.0);
    const std::vector<double> distortion(intrinsics.distortion.begin(), intrinsics.distortion.end());

    // The best single-tag start: the one that explains all the corners best (a tag whose
    // IPPE pose took the mirrored solution explains the other tags badly).
    Pose start;
    double startRms = std::numeric_limits<double>::infinity();
    for (const Pose& candidate : candidates) {
        const double rms = reprojectionRms(candidate, c, cameraMatrix, distortion);
        if (rms < startRms) {
            startRms = rms;
            start = candidate;
        }
    }
    if (!std::isfinite(startRms))
        return false;

    // Solve in the start's orientation (object points turned by its rotation), so the
    // solver's rotation stays near the identity: a map facing the camera is ~180 degrees from
    // the camera frame, where rotation vectors lose precision (see tag_pose.cpp).
    std::vector<cv::Point3d> objectPoints;
    objectPoints.reserve(c.mapPoints.size());
    for (const glm::dvec3& p : c.mapPoints) {
        const glm::dvec3 q = start.R * p;
        objectPoints.emplace_back(q.x, q.y, q.z);
    }
    cv::Vec3d rvec(0.0, 0.0, 0.0);
    cv::Vec3d tvec(start.t.x, start.t.y, start.t.z);
    Pose solved = start;
    double solvedRms = startRms;
    try {
        if (cv::solvePnP(objectPoints, c.imagePoints, cameraMatrix, distortion, rvec, tvec, true,
                         cv::SOLVEPNP_ITERATIVE)) {
            cv::Matx33d cameraFromStart;
            cv::Rodrigues(rvec, cameraFromStart);
            const Pose candidate{toGlm(cameraFromStart * toCv(start.R)), {tvec[0], tvec[1], tvec[2]}};
            const double rms = finite(candidate) ? reprojectionRms(candidate, c, cameraMatrix, distortion)
                                                 : std::numeric_limits<double>::infinity();
            // Levenberg-Marquardt does not go uphill; a worse result means it failed.
            if (rms <= solvedRms) {
                solved = candidate;
                solvedRms = rms;
            }
        }
    } catch (const cv::Exception& e) {
        LUMAR_LOG(Tracking, Debug) << "map " << map.name << ": solvePnP failed: " << e.err;
    }
    if (!(solvedRms <= kMaxMapRmsPx)) {
        LUMAR_LOG(Tracking, Debug) << "map " << map.name << ": reprojection error " << solvedRms << " px";
        return false;
    }
    out.name = map.name;
    out.cameraFromMap = solved;
    out.tagsUsed = int(ids.size());
    out.tagIds = std::move(ids);
    out.reprojectionErrorPx = solvedRms;
    return true;
}

bool projectMapTag(const TagMapTag& tag, const Pose& cameraFromMap, const CameraIntrinsics& intrinsics,
                   std::array<glm::dvec2, 4>& corners)
{
    const Pose cameraFromTag = cameraFromMap * tag.mapFromTag;
    // The tag's +z (out of its face) must point towards the camera, i.e. against its position.
    const glm::dvec3 normal = cameraFromTag.R * glm::dvec3(0.0, 0.0, 1.0);
    if (!(glm::dot(normal, cameraFromTag.t) < 0.0))
        return false;
    std::vector<cv::Point3d> points;
    for (const glm::dvec3& corner : tagCornersInMarkerFrame(tag.size)) {
        const glm::dvec3 p = cameraFromTag.apply(corner);
        if (!(p.z > 0.0))
            return false;
        points.emplace_back(p.x, p.y, p.z);
    }
    const cv::Matx33d cameraMatrix(intrinsics.fx, 0, intrinsics.cx, 0, intrinsics.fy, intrinsics.cy, 0, 0, 1);
    const std::vector<double> distortion(intrinsics.distortion.begin(), intrinsics.distortion.end());
    std::vector<cv::Point2d> projected;
    cv::projectPoints(points, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), cameraMatrix, distortion, projected);
    for (size_t i = 0; i < 4; ++i)
        corners[i] = {projected[i].x, projected[i].y};
    return true;
}

} // namespace lumar
