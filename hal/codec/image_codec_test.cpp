// The codec against OpenCV's imgcodecs (linked by this test only): the same bytes when
// encoding, the same pixels when decoding; and cut or corrupt data gives an error naming
// its source, never a crash.
#include <catch2/catch.hpp>

#include <filesystem>
#include <random>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "hal/codec/image_codec.hpp"

namespace orthosonar::codec {
namespace {

// A deterministic image with smooth structure and noise (JPEG and PNG both have work to do).
cv::Mat test_image(int rows, int cols, int type, uint32_t seed) {
  cv::Mat m(rows, cols, type);
  std::mt19937 rng(seed);
  const int channels = m.channels();
  const bool sixteen = m.depth() == CV_16U;
  for (int y = 0; y < rows; ++y) {
    for (int x = 0; x < cols; ++x) {
      for (int c = 0; c < channels; ++c) {
        const uint32_t v = static_cast<uint32_t>((x * 7 + y * 3 + c * 50) % 256) + rng() % 32;
        if (sixteen) m.ptr<uint16_t>(y)[x * channels + c] = static_cast<uint16_t>((v * 257 + rng() % 256) & 0xFFFF);
        else m.ptr<uint8_t>(y)[x * channels + c] = static_cast<uint8_t>(v & 0xFF);
      }
    }
  }
  return m;
}

bool same_pixels(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0;
}

std::vector<uint8_t> opencv_encode(const std::string& ext, const cv::Mat& m, std::vector<int> params = {}) {
  std::vector<uint8_t> out;
  REQUIRE(cv::imencode(ext, m, out, params));
  return out;
}

cv::Mat opencv_decode(const std::vector<uint8_t>& bytes, int flags) {
  return cv::imdecode(cv::Mat(1, static_cast<int>(bytes.size()), CV_8U, const_cast<uint8_t*>(bytes.data())), flags);
}

}  // namespace

TEST_CASE("codec: PNG encoding gives OpenCV's bytes, and both decoders give the same pixels", "[codec]") {
  for (int type : {CV_8UC1, CV_8UC3, CV_8UC4, CV_16UC1}) {
    CAPTURE(type);
    const cv::Mat m = test_image(37, 53, type, static_cast<uint32_t>(type) + 1);
    auto ours = encode_png(m);
    REQUIRE(ours.ok());
    CHECK(*ours == opencv_encode(".png", m));
    auto gray = decode_image(*ours, DecodeAs::kGray, "test.png");
    REQUIRE(gray.ok());
    CHECK(same_pixels(*gray, opencv_decode(*ours, cv::IMREAD_GRAYSCALE | cv::IMREAD_ANYDEPTH)));
    if (type == CV_8UC1 || type == CV_16UC1) CHECK(same_pixels(*gray, m));  // lossless
    auto bgr = decode_image(*ours, DecodeAs::kBgr, "test.png");
    REQUIRE(bgr.ok());
    CHECK(same_pixels(*bgr, opencv_decode(*ours, cv::IMREAD_COLOR)));
  }
}

TEST_CASE("codec: JPEG encoding gives OpenCV's bytes at each quality, decoding gives its pixels", "[codec]") {
  for (int type : {CV_8UC1, CV_8UC3}) {
    for (int quality : {10, 80, 95, 100}) {
      CAPTURE(type, quality);
      const cv::Mat m = test_image(48, 61, type, static_cast<uint32_t>(quality));
      auto ours = encode_jpeg(m, quality);
      REQUIRE(ours.ok());
      CHECK(*ours == opencv_encode(".jpg", m, {cv::IMWRITE_JPEG_QUALITY, quality}));
      auto gray = decode_image(*ours, DecodeAs::kGray, "test.jpg");
      REQUIRE(gray.ok());
      CHECK(same_pixels(*gray, opencv_decode(*ours, cv::IMREAD_GRAYSCALE | cv::IMREAD_ANYDEPTH)));
      auto bgr = decode_image(*ours, DecodeAs::kBgr, "test.jpg");
      REQUIRE(bgr.ok());
      CHECK(same_pixels(*bgr, opencv_decode(*ours, cv::IMREAD_COLOR)));
      if (quality == 100 && type == CV_8UC1) CHECK(cv::norm(*gray, m, cv::NORM_INF) <= 2);
    }
  }
}

TEST_CASE("codec: bad input is refused with an error naming its source", "[codec]") {
  SECTION("neither format") {
    const std::vector<uint8_t> junk = {1, 2, 3, 4, 5, 6, 7, 8, 9};
    auto r = decode_image(junk, DecodeAs::kGray, "topic /sonar at offset 42");
    REQUIRE_FALSE(r.ok());
    CHECK_THAT(r.error().message, Catch::Contains("topic /sonar at offset 42") && Catch::Contains("neither"));
    CHECK_FALSE(decode_image({}, DecodeAs::kGray, "empty").ok());
  }
  SECTION("every cut of a PNG and of a JPEG, and every single-byte corruption of the headers") {
    const cv::Mat m = test_image(20, 24, CV_8UC1, 7);
    for (const auto& full : {*encode_png(m), *encode_jpeg(m, 80)}) {
      for (size_t n = 0; n < full.size(); ++n) {
        const std::vector<uint8_t> cut(full.begin(), full.begin() + static_cast<std::ptrdiff_t>(n));
        auto r = decode_image(cut, DecodeAs::kGray, "cut.img");
        // libjpeg pads a cut scan with gray (a warning, as OpenCV does); the header must be whole.
        if (!r.ok()) CHECK_THAT(r.error().message, Catch::Contains("cut.img"));
        else CHECK((r->rows == 20 && r->cols == 24));
      }
      for (size_t at = 0; at < std::min<size_t>(full.size(), 64); ++at) {
        std::vector<uint8_t> bad = full;
        bad[at] ^= 0x5A;
        auto r = decode_image(bad, DecodeAs::kBgr, "bad.img");
        if (!r.ok()) CHECK_THAT(r.error().message, Catch::Contains("bad.img"));
      }
    }
    // A PNG cut inside its pixel data is an error (PNG has a checksum and an end chunk).
    const auto png = *encode_png(m);
    const std::vector<uint8_t> half(png.begin(), png.begin() + static_cast<std::ptrdiff_t>(png.size() / 2));
    auto r = decode_image(half, DecodeAs::kGray, "half.png");
    REQUIRE_FALSE(r.ok());
    CHECK_THAT(r.error().message, Catch::Contains("half.png") && Catch::Contains("cut short"));
  }
  SECTION("an image larger than the limit is refused before it is allocated") {
    const cv::Mat m = test_image(100, 100, CV_8UC1, 3);
    auto r = decode_image(*encode_png(m), DecodeAs::kGray, "big.png", 9999);
    REQUIRE_FALSE(r.ok());
    CHECK_THAT(r.error().message, Catch::Contains("100 x 100, more than 9999 pixels"));
    auto j = decode_image(*encode_jpeg(m, 90), DecodeAs::kGray, "big.jpg", 9999);
    REQUIRE_FALSE(j.ok());
    CHECK_THAT(j.error().message, Catch::Contains("big.jpg: the image is 100 x 100"));
    CHECK(decode_image(*encode_png(m), DecodeAs::kGray, "ok.png", 10000).ok());
  }
  SECTION("what cannot be encoded") {
    CHECK_FALSE(encode_png(cv::Mat()).ok());
    CHECK_FALSE(encode_png(cv::Mat(4, 4, CV_32FC1, 0.0f)).ok());
    CHECK_FALSE(encode_jpeg(cv::Mat(4, 4, CV_16UC1), 80).ok());
    CHECK_FALSE(encode_jpeg(cv::Mat(4, 4, CV_8UC1, cv::Scalar(0)), 0).ok());
    CHECK_FALSE(encode_jpeg(cv::Mat(4, 4, CV_8UC1, cv::Scalar(0)), 101).ok());
  }
}

TEST_CASE("codec: files are written whole and read back, a path that cannot be written is named", "[codec]") {
  const auto dir = std::filesystem::temp_directory_path() / "orthosonar_codec_test";
  std::filesystem::create_directories(dir);
  const cv::Mat m = test_image(30, 40, CV_8UC3, 11);
  const std::string png = (dir / "a.png").string(), jpg = (dir / "a.jpg").string();
  REQUIRE(write_png(png, m).ok());
  REQUIRE(write_jpeg(jpg, m, 90).ok());
  auto back = read_image(png, DecodeAs::kBgr);
  REQUIRE(back.ok());
  CHECK(same_pixels(*back, m));
  CHECK(same_pixels(*back, cv::imread(png, cv::IMREAD_COLOR)));
  auto jback = read_image(jpg, DecodeAs::kBgr);
  REQUIRE(jback.ok());
  CHECK(same_pixels(*jback, cv::imread(jpg, cv::IMREAD_COLOR)));
  const Status s = write_png((dir / "no_such_dir" / "b.png").string(), m);
  REQUIRE_FALSE(s.ok());
  CHECK_THAT(s.error().message, Catch::Contains("no_such_dir/b.png"));
  auto missing = read_image((dir / "missing.png").string(), DecodeAs::kGray);
  REQUIRE_FALSE(missing.ok());
  CHECK_THAT(missing.error().message, Catch::Contains("missing.png"));
  std::filesystem::remove_all(dir);
}

}  // namespace orthosonar::codec
