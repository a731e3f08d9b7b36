// solveTagPose: one square tag's pose with OpenCV's IPPE_SQUARE solver (both of its
// solutions), each refined with Levenberg-Marquardt on the reprojection error, the choice
// between them made by error ratio and, when ambiguous, by the tag's previous pose.
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "core/log.h"
#include "tracking/tag_tracker.h"

namespace lumar {
namespace {

// A pose whose corners reproject worse than this is not the tag we saw: the corners were
// not a planar square (a false detection) or the solver ended in a wrong minimum.
constexpr double kMaxReprojectionRmsPx = 4.0;

// Two refined solutions this close (rotation entries, relative translation) are one.
constexpr double kSameSolution = 1e-6;

// A quad smaller than 4x4 px cannot hold a decoded code (the smallest family needs 8 cells
// a side) and its corners' noise would be a large fraction of its side: no usable pose.
constexpr double kMinQuadAreaPx2 = 16.0;

// OpenCV's default stops LM once a step changes the parameters by less than FLT_EPSILON,
// which leaves up to 1e-4 px on exact corners; four points converge in a few more steps.
const cv::TermCriteria kRefineCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-12);

// Corner signs (x, y) of the tag in our marker frame, in the AprilTag order (core/pose.h),
// and IPPE_SQUARE's required object point order.
constexpr int kMarkerCornerSigns[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
constexpr int kIppeCornerSigns[4][2] = {{-1, 1}, {1, 1}, {1, -1}, {-1, -1}};

// The frame the solver works in: the marker frame turned 180 degrees about x (so its z
// points away from the camera like the camera's own z) and then by `quarterTurns` x 90
// degrees about z. The square's corners land on corners again, so IPPE_SQUARE's fixed
// object points still apply, only matched to different image points.
//
// Why not solve in the marker frame directly: OpenCV's IPPE returns a rotation vector and
// converts its rotation matrix with a formula that divides by sin(angle). A tag facing the
// camera is a rotation by ~180 degrees from our marker frame, where that division loses
// every digit (measured: 0.2-0.3 rad errors, or NaN, with exact corners). Choosing the
// quarter turn that best aligns the solver's x axis with the image's x axis keeps the
// solver's rotation within about tilt + 45 degrees of the identity.
struct SolverFrame {
    int quarterTurns = 0;

    // solver_from_marker, exact (entries 0 and +-1).
    [[nodiscard]] cv::Matx33d solverFromMarker() const
    {
        cv::Matx33d r = cv::Matx33d::eye();
        for (int i = 0; i < quarterTurns; ++i)
            r = cv::Matx33d(0, -1, 0, 1, 0, 0, 0, 0, 1) * r;
        return r * cv::Matx33d(1, 0, 0, 0, -1, 0, 0, 0, -1);
    }

    // Index into IPPE_SQUARE's order of marker corner `i`.
    [[nodiscard]] int ippeIndexOf(int i) const
    {
        int x = kMarkerCornerSigns[i][0];
        int y = -kMarkerCornerSigns[i][1]; // the 180 degree turn about x
        for (int k = 0; k < quarterTurns; ++k) {
            const int rotatedX = -y;
            y = x;
            x = rotatedX;
        }
        for (int j = 0; j < 4; ++j)
            if (kIppeCornerSigns[j][0] == x && kIppeCornerSigns[j][1] == y)
                return j;
        return -1; // unreachable: a quarter turn maps corners onto corners
    }
};

// Quarter turns in order of preference: the solver's x axis as close as possible to the
// image's +x direction, judged from the tag's edges in the image.
std::array<int, 4> quarterTurnPreference(const std::array<glm::dvec2, 4>& p)
{
    const glm::dvec2 markerX = (p[1] - p[0]) + (p[2] - p[3]);
    const glm::dvec2 markerY = (p[3] - p[0]) + (p[2] - p[1]);
    // Solver x in marker coordinates is (cos 90k, sin 90k): +x, +y, -x, -y.
    const std::array<glm::dvec2, 4> solverX{markerX, markerY, -markerX, -markerY};
    std::array<double, 4> alignment{};
    for (size_t k = 0; k < 4; ++k) {
        const double length = glm::length(solverX[k]);
        alignment[k] = length > 0.0 ? solverX[k].x / length : -2.0;
    }
    std::array<int, 4> order{0, 1, 2, 3};
    std::sort(order.begin(), order.end(), [&](int a, int b) { return alignment[size_t(a)] > alignment[size_t(b)]; });
    return order;
}

bool allFinite(const cv::Matx33d& m, const cv::Vec3d& t)
{
    for (double v : m.val)
        if (!std::isfinite(v))
            return false;
    return std::isfinite(t[0]) && std::isfinite(t[1]) && std::isfinite(t[2]);
}

double reprojectionRms(const std::vector<cv::Point3d>& objectPoints, const std::vector<cv::Point2d>& imagePoints,
                       const cv::Vec3d& rvec, const cv::Vec3d& tvec, const cv::Matx33d& cameraMatrix,
                       const std::vector<double>& distortion)
{
    std::vector<cv::Point2d> reprojected;
    cv::projectPoints(objectPoints, rvec, tvec, cameraMatrix, distortion, reprojected);
    double sumSquares = 0.0;
    for (size_t i = 0; i < imagePoints.size(); ++i) {
        const cv::Point2d d = reprojected[i] - imagePoints[i];
        sumSquares += d.dot(d);
    }
    return std::sqrt(sumSquares / double(imagePoints.size()));
}

struct Solution {
    cv::Matx33d R; // camera_from_marker
    cv::Vec3d t;
    double rms = 0.0;
};

// Refines one IPPE solution (rvec/tvec in the solver frame) with Levenberg-Marquardt on the
// reprojection error through the full distortion model (IPPE alone undistorts the corners
// with a few fixed-point iterations) and converts it to camera_from_marker.
bool refineSolution(const SolverFrame& frame, const std::vector<cv::Point3d>& objectPoints,
                    const std::vector<cv::Point2d>& imagePoints, const cv::Matx33d& cameraMatrix,
                    const std::vector<double>& distortion, cv::Vec3d rvec, cv::Vec3d tvec, Solution& out)
{
    if (!std::isfinite(rvec[0]) || !std::isfinite(rvec[1]) || !std::isfinite(rvec[2]))
        return false;
    double rms = reprojectionRms(objectPoints, imagePoints, rvec, tvec, cameraMatrix, distortion);

    cv::Vec3d refinedR = rvec;
    cv::Vec3d refinedT = tvec;
    cv::solvePnPRefineLM(objectPoints, imagePoints, cameraMatrix, distortion, refinedR, refinedT, kRefineCriteria);
    const double refinedRms = reprojectionRms(objectPoints, imagePoints, refinedR, refinedT, cameraMatrix, distortion);
    if (std::isfinite(refinedRms) && refinedRms <= rms) {
        rvec = refinedR;
        tvec = refinedT;
        rms = refinedRms;
    }

    cv::Matx33d cameraFromSolver;
    cv::Rodrigues(rvec, cameraFromSolver);
    out.R = cameraFromSolver * frame.solverFromMarker();
    out.t = tvec;
    out.rms = rms;
    return std::isfinite(rms) && allFinite(out.R, out.t);
}

// Both IPPE solutions in one solver frame, each refined; `count` of them are valid, the
// first always the one with the lower error. Throws cv::Exception for degenerate corners.
bool solveInFrame(const SolverFrame& frame, const std::array<glm::dvec2, 4>& corners, double tagSize,
                  const cv::Matx33d& cameraMatrix, const std::vector<double>& distortion,
                  std::array<Solution, 2>& solutions, int& count)
{
    const double h = 0.5 * tagSize;
    std::vector<cv::Point3d> objectPoints(4);
    std::vector<cv::Point2d> imagePoints(4);
    for (int j = 0; j < 4; ++j)
        objectPoints[size_t(j)] = {kIppeCornerSigns[j][0] * h, kIppeCornerSigns[j][1] * h, 0.0};
    for (int i = 0; i < 4; ++i) {
        const auto j = size_t(frame.ippeIndexOf(i));
        imagePoints[j] = {corners[size_t(i)].x, corners[size_t(i)].y};
    }

    // Distortion goes to the solver, which undistorts the four corners; the image itself is
    // never undistorted (DESIGN.md §5).
    std::vector<cv::Mat> rvecs;
    std::vector<cv::Mat> tvecs;
    const int found = cv::solvePnPGeneric(objectPoints, imagePoints, cameraMatrix, distortion, rvecs, tvecs, false,
                                          cv::SOLVEPNP_IPPE_SQUARE);
    count = 0;
    for (int i = 0; i < found && i < 2; ++i) {
        const cv::Vec3d rvec(rvecs[size_t(i)].reshape(1, 3));
        const cv::Vec3d tvec(tvecs[size_t(i)].reshape(1, 3));
        Solution s;
        // A NaN in the better solution means this frame hit the solver's singular case.
        if (!refineSolution(frame, objectPoints, imagePoints, cameraMatrix, distortion, rvec, tvec, s))
            return i > 0;
        solutions[size_t(count++)] = s;
    }
    if (count == 2 && solutions[1].rms < solutions[0].rms)
        std::swap(solutions[0], solutions[1]);
    // Refinement can carry IPPE's second solution into the first one's minimum (the second
    // was no minimum of the full error): then there is one solution, not an ambiguity.
    if (count == 2 && cv::norm(solutions[0].R - solutions[1].R, cv::NORM_INF) < kSameSolution &&
        cv::norm(solutions[0].t - solutions[1].t) < kSameSolution * cv::norm(solutions[0].t))
        count = 1;
    return count > 0;
}

Pose toPose(const Solution& s)
{
    Pose pose;
    // cv::Matx is row-major, glm column-major.
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col)
            pose.R[col][row] = s.R(row, col);
    pose.t = {s.t[0], s.t[1], s.t[2]};
    return pose;
}

// Angle of the rotation between `a` and `b`, radians.
double rotationDistance(const glm::dmat3& a, const glm::dmat3& b)
{
    const glm::dmat3 d = glm::transpose(a) * b;
    return std::acos(std::clamp((d[0][0] + d[1][1] + d[2][2] - 1.0) / 2.0, -1.0, 1.0));
}

// Not a pose of what we saw: a tag behind the camera (every corner must lie in front of it,
// not only the centre), or a tag seen from its back (the camera must be on the side its +z
// points to; a printed tag cannot be decoded from behind, so this means mirrored, clockwise
// corners).
bool plausible(const Solution& s, double tagSize)
{
    const double h = 0.5 * tagSize;
    if (s.t[2] <= 0.0)
        return false;
    for (const auto& sign : kMarkerCornerSigns)
        if ((s.R * cv::Vec3d(sign[0] * h, sign[1] * h, 0.0) + s.t)[2] <= 0.0)
            return false;
    const cv::Vec3d markerNormal(s.R(0, 2), s.R(1, 2), s.R(2, 2));
    return markerNormal.dot(s.t) < 0.0;
}

// The image of a square in front of a camera is a convex quad (a central projection keeps
// convexity on the visible side); a crossed or dented quad is no tag. Returns the absolute
// area, or 0 for a non-convex quad.
double convexQuadArea(const std::array<glm::dvec2, 4>& p)
{
    double area = 0.0;
    int positive = 0, negative = 0;
    for (size_t i = 0; i < 4; ++i) {
        const glm::dvec2 a = p[(i + 1) % 4] - p[i];
        const glm::dvec2 b = p[(i + 2) % 4] - p[(i + 1) % 4];
        const double turn = a.x * b.y - a.y * b.x;
        (turn > 0.0 ? positive : negative) += 1;
        area += p[i].x * p[(i + 1) % 4].y - p[(i + 1) % 4].x * p[i].y;
    }
    return positive == 4 || negative == 4 ? 0.5 * std::abs(area) : 0.0;
}

} // namespace

bool solveTagPose(const std::array<glm::dvec2, 4>& corners, double tagSize, const CameraIntrinsics& intrinsics,
                  TagPoseSolution& out, const Pose* previous)
{
    if (!(tagSize > 0.0) || !std::isfinite(tagSize))
        return false;
    for (const glm::dvec2& c : corners)
        if (!std::isfinite(c.x) || !std::isfinite(c.y))
            return false;
    const double area = convexQuadArea(corners);
    if (area < kMinQuadAreaPx2)
        return false;

    const cv::Matx33d cameraMatrix(intrinsics.fx, 0.0, intrinsics.cx, 0.0, intrinsics.fy, intrinsics.cy, 0.0, 0.0, 1.0);
    const std::vector<double> distortion(intrinsics.distortion.begin(), intrinsics.distortion.end());

    std::array<Solution, 2> solutions;
    int count = 0;
    bool found = false;
    // The preferred frame almost always works; the next one is a fallback for the rare
    // exact-identity case where the solver's acos((trace - 1) / 2) sees a trace just above 3.
    for (int quarterTurns : quarterTurnPreference(corners)) {
        try {
            found =
                solveInFrame(SolverFrame{quarterTurns}, corners, tagSize, cameraMatrix, distortion, solutions, count);
        } catch (const cv::Exception& e) {
            // Degenerate corners (collinear, coincident) make the solver's maths fail.
            LUMAR_LOG(Tracking, Debug) << "solvePnP failed: " << e.err;
            return false;
        }
        if (found)
            break;
    }
    if (!found)
        return false;

    // Only plausible solutions compete (the second is often a tag seen from behind).
    if (count == 2 && !plausible(solutions[1], tagSize))
        count = 1;
    if (!plausible(solutions[0], tagSize)) {
        if (count < 2)
            return false;
        solutions[0] = solutions[1];
        count = 1;
    }

    // Each refined solution is a local minimum of the same error; the ratio says how clearly
    // the better one wins. Exact corners leave the better one at ~1e-12 px, hence the floor.
    double ratio = kMaxAmbiguityRatio;
    if (count == 2)
        ratio = std::min(kMaxAmbiguityRatio, solutions[1].rms / std::max(solutions[0].rms, 1e-9));
    size_t chosen = 0;
    if (count == 2 && ratio < kAmbiguousRatio && previous) {
        const double d0 = rotationDistance(toPose(solutions[0]).R, previous->R);
        const double d1 = rotationDistance(toPose(solutions[1]).R, previous->R);
        if (d1 < d0)
            chosen = 1;
    }

    // A projected square with 4 corners leaves 2 degrees of freedom to the residual, so its
    // RMS is about half the corner noise: a fraction of a pixel for a real tag. 5 % of the
    // side (at least 1 px, at most 4 px) rejects quads that are no square (false detections)
    // without rejecting a blurred tag whose corners are off by a pixel or two.
    const double maxRms = std::clamp(0.05 * std::sqrt(area), 1.0, kMaxReprojectionRmsPx);
    if (solutions[chosen].rms > maxRms)
        return false;

    out.cameraFromMarker = toPose(solutions[chosen]);
    out.rmsErrorPx = solutions[chosen].rms;
    out.ambiguityRatio = ratio;
    out.choseByPrevious = chosen == 1;
    return true;
}

bool solveTagPose(const std::array<glm::dvec2, 4>& corners, double tagSize, const CameraIntrinsics& intrinsics,
                  Pose& cameraFromMarker, double& rmsErrorPx)
{
    TagPoseSolution solution;
    if (!solveTagPose(corners, tagSize, intrinsics, solution))
        return false;
    cameraFromMarker = solution.cameraFromMarker;
    rmsErrorPx = solution.rmsErrorPx;
    return true;
}

} // namespace lumar
