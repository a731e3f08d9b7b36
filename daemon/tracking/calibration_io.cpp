#include "tracking/calibration_io.h"

#include <charconv>
#include <cmath>
#include <ctime>
#include <string>
#include <system_error>

#include <opencv2/core.hpp>

#include "core/error.h"
#include "core/file_bytes.h"
#include "core/log.h"
#include "tracking/calibration_yaml.h"

namespace lumar {
namespace {

constexpr int kMaxImageSide = 16384;
// OpenCV's distortion vectors have 4, 5, 8, 12 or 14 terms; lumar's model is the first five.
constexpr int kDistortionTermsUsed = 5;
constexpr int kMaxMatrixSide = 16; // the largest: 14 distortion terms

// cv::Exception::err is the bare message; it may still span lines (YAML parser context).
std::string oneLine(std::string text)
{
    for (char& c : text)
        if (c == '\n' || c == '\r')
            c = ' ';
    while (!text.empty() && text.back() == ' ')
        text.pop_back();
    return text;
}

class CalibrationReader {
public:
    explicit CalibrationReader(const std::filesystem::path& file) : name_(file.string()) {}

    [[noreturn]] void fail(const std::string& what) const { throw InputError(name_ + ": " + what); }

    CameraIntrinsics read(const calibration_yaml::Document& document) const
    {
        CameraIntrinsics k;
        k.width = readSide(document, "image_width");
        k.height = readSide(document, "image_height");
        readCameraMatrix(document, k);
        readDistortion(document, k);
        return k;
    }

private:
    const calibration_yaml::Value& required(const calibration_yaml::Document& document, const char* key) const
    {
        const auto found = document.find(key);
        if (found == document.end())
            fail(std::string("missing key '") + key + "'");
        return found->second;
    }

    int readSide(const calibration_yaml::Document& document, const char* key) const
    {
        const calibration_yaml::Value& node = required(document, key);
        int value = 0;
        const std::string& text = node.scalar;
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (node.kind != calibration_yaml::Value::Kind::Scalar || text.empty() || end != text.data() + text.size())
            fail(std::string(key) + ": expected an integer");
        if (ec != std::errc() || value < 1 || value > kMaxImageSide)
            fail(std::string(key) + ": " + text + " is outside 1.." + std::to_string(kMaxImageSide));
        return value;
    }

    const calibration_yaml::Matrix& readMatrix(const calibration_yaml::Document& document, const char* key) const
    {
        const calibration_yaml::Value& node = required(document, key);
        if (node.kind != calibration_yaml::Value::Kind::Matrix)
            fail(std::string(key) + ": expected an !!opencv-matrix");
        const calibration_yaml::Matrix& m = *node.matrix;
        if (m.rows > kMaxMatrixSide || m.cols > kMaxMatrixSide)
            fail(std::string(key) + ": expected an !!opencv-matrix with 1.." + std::to_string(kMaxMatrixSide) +
                 " rows and columns");
        for (const double v : m.data)
            if (!std::isfinite(v))
                fail(std::string(key) + ": values must be finite");
        return m;
    }

    void readCameraMatrix(const calibration_yaml::Document& document, CameraIntrinsics& k) const
    {
        const calibration_yaml::Matrix& m = readMatrix(document, "camera_matrix");
        if (m.rows != 3 || m.cols != 3)
            fail("camera_matrix: expected 3x3, got " + std::to_string(m.rows) + "x" + std::to_string(m.cols));
        const auto at = [&](int r, int c) { return m.data[size_t(r * 3 + c)]; };
        // lumar's camera model has no skew: a matrix with one would be silently wrong.
        if (at(0, 1) != 0.0 || at(1, 0) != 0.0 || at(2, 0) != 0.0 || at(2, 1) != 0.0 || at(2, 2) != 1.0)
            fail("camera_matrix: expected the form [fx 0 cx; 0 fy cy; 0 0 1]");
        k.fx = at(0, 0);
        k.fy = at(1, 1);
        k.cx = at(0, 2);
        k.cy = at(1, 2);
        if (!(k.fx > 0.0) || !(k.fy > 0.0))
            fail("camera_matrix: fx and fy must be positive");
        if (!(k.cx >= 0.0 && k.cx < k.width) || !(k.cy >= 0.0 && k.cy < k.height))
            fail("camera_matrix: the principal point must lie inside the " + std::to_string(k.width) + "x" +
                 std::to_string(k.height) + " image");
    }

    void readDistortion(const calibration_yaml::Document& document, CameraIntrinsics& k) const
    {
        const calibration_yaml::Matrix& d = readMatrix(document, "distortion_coefficients");
        const int n = int(d.data.size());
        if ((d.rows != 1 && d.cols != 1) || (n != 4 && n != 5 && n != 8 && n != 12 && n != 14))
            fail("distortion_coefficients: expected a vector of 4, 5, 8, 12 or 14 values");
        for (int i = 0; i < n; ++i) {
            const double v = d.data[size_t(i)];
            if (i < kDistortionTermsUsed)
                k.distortion[size_t(i)] = v;
            else if (v != 0.0)
                fail("distortion_coefficients: only k1 k2 p1 p2 k3 are supported, coefficient " + std::to_string(i) +
                     " is not zero");
        }
    }

    std::string name_;
};

std::string utcTimestamp()
{
    const std::time_t now = std::time(nullptr);
    std::tm utc{};
    gmtime_r(&now, &utc);
    char text[32];
    const size_t n = std::strftime(text, sizeof(text), "%Y-%m-%dT%H:%M:%SZ", &utc);
    return std::string(text, n);
}

} // namespace

CameraIntrinsics loadCalibration(const std::filesystem::path& file)
{
    const CalibrationReader reader(file);
    std::error_code ec;
    if (!std::filesystem::exists(file, ec))
        reader.fail("cannot read: no such file");
    std::vector<uint8_t> bytes;
    try {
        bytes = readFileBytes(file, calibration_yaml::kMaxFileBytes);
    } catch (const InputError& e) {
        reader.fail(std::string("cannot read: ") + e.what());
    }
    if (bytes.empty())
        reader.fail("empty file");
    const calibration_yaml::Document document = calibration_yaml::parse(
        std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), file.string());
    const CameraIntrinsics k = reader.read(document);
    LUMAR_LOG(Tracking, Info) << "calibration " << file.string() << ": " << k.width << "x" << k.height << " fx " << k.fx
                              << " fy " << k.fy << " cx " << k.cx << " cy " << k.cy;
    return k;
}

void saveCalibration(const std::filesystem::path& file, const CameraIntrinsics& intrinsics,
                     std::optional<double> reprojectionRmsPx)
{
    const std::string name = file.string();
    // Checked here because OpenCV would log its own error line before failing.
    std::error_code ec;
    const std::filesystem::path parent = file.parent_path().empty() ? "." : file.parent_path();
    if (!std::filesystem::is_directory(parent, ec))
        throw RuntimeError(name + ": cannot write: no directory " + parent.string());
    try {
        cv::FileStorage fs(name, cv::FileStorage::WRITE | cv::FileStorage::FORMAT_YAML);
        if (!fs.isOpened())
            throw RuntimeError(name + ": cannot open for writing");
        const cv::Matx33d cameraMatrix(intrinsics.fx, 0.0, intrinsics.cx, 0.0, intrinsics.fy, intrinsics.cy, 0.0, 0.0,
                                       1.0);
        const cv::Matx<double, 1, 5> distortion(intrinsics.distortion.data());
        fs << "calibration_time" << utcTimestamp();
        fs << "image_width" << intrinsics.width;
        fs << "image_height" << intrinsics.height;
        fs << "camera_matrix" << cv::Mat(cameraMatrix);
        fs << "distortion_coefficients" << cv::Mat(distortion);
        if (reprojectionRmsPx)
            fs << "avg_reprojection_error" << *reprojectionRmsPx;
        fs.release();
    } catch (const cv::Exception& e) {
        throw RuntimeError(name + ": cannot write: " + oneLine(e.err));
    }
}

} // namespace lumar
