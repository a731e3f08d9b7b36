// Reading a camera calibration file: the YAML that OpenCV's FileStorage writes (`lumar
// calibrate`, OpenCV's calibration sample), parsed here instead of by OpenCV.
//
// Why not cv::FileStorage: it guesses XML, YAML or JSON from the content and its parsers
// trust the input. Fuzzed, a dozen small files (an XML prolog with NUL bytes, a YAML header
// inside XML, `[[[[` nested deeply, an overlong number) segfaulted lumar 4.6's FileStorage and
// fifteen more kept it busy for over 20 s (issue 16). Guards in front of it would have to know
// every such path; the files lumar reads use a small, fixed part of YAML, which this reads
// in one linear pass with bounded nesting (a flow sequence of scalars at most):
//
//   %YAML:1.0                       optional directive, then an optional "---"
//   key: scalar                     top-level keys at column 0: numbers, plain or quoted text
//   key: [ 1, 2, 3 ]                a flow sequence of scalars, which may continue on
//                                   indented lines
//   key: !!opencv-matrix            an OpenCV matrix: indented rows, cols, dt (one type
//      rows: 3                      letter: a single-channel matrix) and data
//      cols: 3
//      dt: d
//      data: [ 1., 0., ... ]
//   key:                            any other nested block: its indented lines are skipped
//     ...
//   # comments, blank lines
//
// XML and JSON FileStorage files are refused with a message that says so.
#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace lumar::calibration_yaml {

// A calibration file is a few kilobytes (OpenCV's sample with 13 views: 4 KB).
inline constexpr size_t kMaxFileBytes = size_t(1) << 20;
// Elements of one matrix; per-view extrinsics of a few thousand views still fit.
inline constexpr size_t kMaxMatrixElements = size_t(1) << 16;

struct Matrix {
    int rows = 0;
    int cols = 0;
    char type = 'd'; // OpenCV's dt letter: u c w s i f d
    std::vector<double> data;
};

struct Value {
    enum class Kind { Scalar, Sequence, Matrix, Block };
    Kind kind = Kind::Scalar;
    size_t line = 0;
    std::string scalar;               // Kind::Scalar: the text, quotes removed
    std::optional<Matrix> matrix;     // Kind::Matrix
    std::vector<std::string> entries; // Kind::Sequence
};

using Document = std::map<std::string, Value, std::less<>>;

// Throws InputError "FILE:LINE: malformed file: what" (or "FILE: ..." where no line applies)
// for anything outside the subset above, and "FILE: KEY: not a valid !!opencv-matrix (...)"
// for a matrix whose fields do not fit together.
Document parse(std::string_view text, const std::string& fileName);

// A scalar as a number: decimal, YAML's .inf/.nan spellings included. nullopt if it is not one.
std::optional<double> toNumber(std::string_view text);

} // namespace lumar::calibration_yaml
