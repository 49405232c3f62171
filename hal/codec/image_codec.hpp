#pragma once
// PNG and JPEG images to and from bytes and files, with libpng and libjpeg-turbo directly.
// Encoding gives the bytes OpenCV's cv::imencode gives for the same image and options
// (PNG: filter SUB, zlib level 1, Z_RLE; JPEG: baseline, jpeg_set_quality), and decoding
// gives the pixels cv::imdecode gives (IMREAD_GRAYSCALE | IMREAD_ANYDEPTH, or
// IMREAD_COLOR), except that a JPEG's EXIF orientation is not applied; image_codec_test.cpp
// checks both against OpenCV. Images are cv::Mat as OpenCV holds them: 8-bit gray, BGR or
// BGRA, or 16-bit gray (PNG only).
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "core/result.hpp"

namespace orthosonar::codec {

// What a decoded image becomes.
enum class DecodeAs {
  kGray,  // one channel; 16-bit PNGs stay 16-bit (CV_16U), everything else CV_8U; colour
          // is converted as OpenCV converts it (libpng's rgb_to_gray 0.299/0.587, libjpeg's YCbCr Y)
  kBgr,   // three 8-bit channels in OpenCV's order; gray is replicated, 16-bit keeps the high byte
};

// Images larger than this many pixels (as their header states) are refused before anything
// is allocated for them.
inline constexpr uint64_t kDefaultMaxPixels = uint64_t{1} << 26;

// `what` names the source in error messages (a file, or "topic X at offset Y").
Result<cv::Mat> decode_image(std::span<const uint8_t> bytes, DecodeAs as, const std::string& what,
                             uint64_t max_pixels = kDefaultMaxPixels);

// PNG of an 8-bit 1-, 3- (BGR) or 4-channel (BGRA) image, or a 16-bit one-channel image.
Result<std::vector<uint8_t>> encode_png(const cv::Mat& image);

// Baseline JPEG of an 8-bit 1- or 3-channel (BGR) image; quality 1..100.
Result<std::vector<uint8_t>> encode_jpeg(const cv::Mat& image, int quality);

// Files: the parent folder must exist; the file is written whole or an error is returned.
Status write_png(const std::string& path, const cv::Mat& image);
Status write_jpeg(const std::string& path, const cv::Mat& image, int quality);
Result<cv::Mat> read_image(const std::string& path, DecodeAs as, uint64_t max_pixels = kDefaultMaxPixels);

}  // namespace orthosonar::codec
