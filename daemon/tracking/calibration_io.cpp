#include "tracking/calibration_io.h"

#include <cmath>
#include <ctime>
#include <string>
#include <system_error>

#include <opencv2/core.hpp>

#include "core/error.h"
#include "core/log.h"

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

    CameraIntrinsics read(const cv::FileStorage& fs) const
    {
        CameraIntrinsics k;
        k.width = readSide(fs, "image_width");
        k.height = readSide(fs, "image_height");
        readCameraMatrix(fs, k);
        readDistortion(fs, k);
        return k;
    }

private:
    cv::FileNode required(const cv::FileStorage& fs, const char* key) const
    {
        const cv::FileNode node = fs[key];
        if (node.empty() || node.isNone())
            fail(std::string("missing key '") + key + "'");
        return node;
    }

    int readSide(const cv::FileStorage& fs, const char* key) const
    {
        const cv::FileNode node = required(fs, key);
        if (!node.isInt())
            fail(std::string(key) + ": expected an integer");
        const int value = int(node);
        if (value < 1 || value > kMaxImageSide)
            fail(std::string(key) + ": " + std::to_string(value) + " is outside 1.." + std::to_string(kMaxImageSide));
        return value;
    }

    cv::Mat readMatrix(const cv::FileStorage& fs, const char* key) const
    {
        const cv::FileNode node = required(fs, key);
        if (!node.isMap())
            fail(std::string(key) + ": expected an !!opencv-matrix");
        // OpenCV allocates rows x cols before it counts the data: bound them first.
        const cv::FileNode rows = node["rows"];
        const cv::FileNode cols = node["cols"];
        if (!rows.isInt() || !cols.isInt() || int(rows) < 1 || int(rows) > kMaxMatrixSide || int(cols) < 1 ||
            int(cols) > kMaxMatrixSide)
            fail(std::string(key) + ": expected an !!opencv-matrix with 1.." + std::to_string(kMaxMatrixSide) +
                 " rows and columns");
        cv::Mat m;
        try {
            node >> m;
        } catch (const cv::Exception& e) {
            fail(std::string(key) + ": not a valid !!opencv-matrix (" + oneLine(e.err) + ")");
        }
        if (m.empty() || m.channels() != 1)
            fail(std::string(key) + ": expected a single-channel !!opencv-matrix");
        cv::Mat asDouble;
        m.convertTo(asDouble, CV_64F);
        for (int r = 0; r < asDouble.rows; ++r)
            for (int c = 0; c < asDouble.cols; ++c)
                if (!std::isfinite(asDouble.at<double>(r, c)))
                    fail(std::string(key) + ": values must be finite");
        return asDouble;
    }

    void readCameraMatrix(const cv::FileStorage& fs, CameraIntrinsics& k) const
    {
        const cv::Mat m = readMatrix(fs, "camera_matrix");
        if (m.rows != 3 || m.cols != 3)
            fail("camera_matrix: expected 3x3, got " + std::to_string(m.rows) + "x" + std::to_string(m.cols));
        // lumar's camera model has no skew: a matrix with one would be silently wrong.
        if (m.at<double>(0, 1) != 0.0 || m.at<double>(1, 0) != 0.0 || m.at<double>(2, 0) != 0.0 ||
            m.at<double>(2, 1) != 0.0 || m.at<double>(2, 2) != 1.0)
            fail("camera_matrix: expected the form [fx 0 cx; 0 fy cy; 0 0 1]");
        k.fx = m.at<double>(0, 0);
        k.fy = m.at<double>(1, 1);
        k.cx = m.at<double>(0, 2);
        k.cy = m.at<double>(1, 2);
        if (!(k.fx > 0.0) || !(k.fy > 0.0))
            fail("camera_matrix: fx and fy must be positive");
        if (!(k.cx >= 0.0 && k.cx < k.width) || !(k.cy >= 0.0 && k.cy < k.height))
            fail("camera_matrix: the principal point must lie inside the " + std::to_string(k.width) + "x" +
                 std::to_string(k.height) + " image");
    }

    void readDistortion(const cv::FileStorage& fs, CameraIntrinsics& k) const
    {
        const cv::Mat d = readMatrix(fs, "distortion_coefficients");
        const int n = int(d.total());
        if ((d.rows != 1 && d.cols != 1) || (n != 4 && n != 5 && n != 8 && n != 12 && n != 14))
            fail("distortion_coefficients: expected a vector of 4, 5, 8, 12 or 14 values");
        const cv::Mat flat = d.reshape(1, 1);
        for (int i = 0; i < n; ++i) {
            const double v = flat.at<double>(0, i);
            if (i < kDistortionTermsUsed)
                k.distortion[size_t(i)] = v;
            else if (v != 0.0)
                fail("distortion_coefficients: only k1 k2 p1 p2 k3 are supported, coefficient " + std::to_string(i) +
                     " is not zero");
        }
    }

    std::string name_;
};

// OpenCV's YAML/XML/JSON parsers throw StsParseError with "FILE(LINE): what" in the
// exception's `func` field; other failures only have a terse `err`.
std::string describeParseFailure(const cv::Exception& e, const std::string& fileName)
{
    if (e.code == cv::Error::StsParseError) {
        const std::string where = oneLine(e.func);
        const size_t close = where.find("): ");
        const size_t open = where.rfind('(', close);
        if (close != std::string::npos && open != std::string::npos && open + 1 < close &&
            where.find_first_not_of("0123456789", open + 1) == close)
            return fileName + ":" + where.substr(open + 1, close - open - 1) +
                   ": malformed file: " + where.substr(close + 3);
        return fileName + ": malformed file: " + where;
    }
    return fileName + ": cannot parse: " + oneLine(e.err);
}

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
    if (!std::filesystem::is_regular_file(file, ec))
        reader.fail("cannot read: not a regular file");
    if (std::filesystem::file_size(file, ec) == 0 && !ec)
        reader.fail("empty file");
    try {
        cv::FileStorage fs(file.string(), cv::FileStorage::READ);
        if (!fs.isOpened())
            reader.fail("cannot read as OpenCV FileStorage");
        const CameraIntrinsics k = reader.read(fs);
        LUMAR_LOG(Tracking, Info) << "calibration " << file.string() << ": " << k.width << "x" << k.height << " fx "
                                  << k.fx << " fy " << k.fy << " cx " << k.cx << " cy " << k.cy;
        return k;
    } catch (const InputError&) {
        throw;
    } catch (const cv::Exception& e) {
        // OpenCV's parser reports malformed files by throwing.
        throw InputError(describeParseFailure(e, file.string()));
    } catch (const std::exception& e) {
        // Malformed input can trip standard-library errors inside OpenCV's parser
        // (measured: std::length_error for a matrix whose 'dt' key reads ':dt').
        throw InputError(file.string() + ": cannot parse: " + oneLine(e.what()));
    }
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
