// PNG and JPEG with libpng and libjpeg-turbo (image_codec.hpp). Both libraries report
// errors by longjmp: every object that must survive one lives in a heap context created
// before setjmp, so no C++ object is left half-built and nothing leaks.
#include "hal/codec/image_codec.hpp"

#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>

#include <jpeglib.h>
#include <png.h>
#include <zlib.h>

namespace orthosonar::codec {
namespace {

constexpr uint8_t kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

bool is_png(std::span<const uint8_t> b) { return b.size() >= 8 && std::memcmp(b.data(), kPngSignature, 8) == 0; }
bool is_jpeg(std::span<const uint8_t> b) { return b.size() >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF; }

// ---------------------------------------------------------------- PNG

struct PngContext {
  std::span<const uint8_t> in;  // decoding: the bytes and how far libpng has read
  size_t pos = 0;
  std::vector<uint8_t> out;     // encoding: what libpng wrote
  cv::Mat image;                // decoding: the image being filled
  std::vector<png_bytep> rows;
  std::string message;          // libpng's error
  std::jmp_buf jump;
};

void png_on_error(png_structp png, png_const_charp msg) {
  auto* c = static_cast<PngContext*>(png_get_error_ptr(png));
  c->message = msg;
  std::longjmp(c->jump, 1);
}
void png_on_warning(png_structp, png_const_charp) {}

void png_read_bytes(png_structp png, png_bytep dst, png_size_t n) {
  auto* c = static_cast<PngContext*>(png_get_io_ptr(png));
  if (n > c->in.size() - c->pos) png_error(png, "the data ends inside the image (file cut short?)");
  std::memcpy(dst, c->in.data() + c->pos, n);
  c->pos += n;
}
void png_write_bytes(png_structp png, png_bytep src, png_size_t n) {
  auto* c = static_cast<PngContext*>(png_get_io_ptr(png));
  c->out.insert(c->out.end(), src, src + n);
}
void png_flush_nothing(png_structp) {}

struct PngRead {
  png_structp png = nullptr;
  png_infop info = nullptr;
  ~PngRead() { png_destroy_read_struct(&png, info ? &info : nullptr, nullptr); }
};
struct PngWrite {
  png_structp png = nullptr;
  png_infop info = nullptr;
  ~PngWrite() { png_destroy_write_struct(&png, info ? &info : nullptr); }
};

// Fills c.image; false (c.message set) when libpng fails.
bool png_decode_into(PngContext& c, PngRead& r, DecodeAs as, uint64_t max_pixels, std::string& limit_error) {
  if (setjmp(c.jump)) return false;
  png_set_read_fn(r.png, &c, png_read_bytes);
  png_read_info(r.png, r.info);
  png_uint_32 width = 0, height = 0;
  int depth = 0, color = 0;
  png_get_IHDR(r.png, r.info, &width, &height, &depth, &color, nullptr, nullptr, nullptr);
  if (static_cast<uint64_t>(width) * height > max_pixels) {
    limit_error = "the image is " + std::to_string(height) + " x " + std::to_string(width) + ", more than " +
                  std::to_string(max_pixels) + " pixels";
    return true;
  }
  const bool keep16 = as == DecodeAs::kGray && depth > 8;
  // The transformations OpenCV's PNG decoder asks of libpng, in its order.
  if (depth > 8 && !keep16) png_set_strip_16(r.png);
  else if (keep16) png_set_swap(r.png);  // little-endian host
  png_set_strip_alpha(r.png);
  if (color == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(r.png);
  if ((color & PNG_COLOR_MASK_COLOR) == 0 && depth < 8) png_set_expand_gray_1_2_4_to_8(r.png);
  if (as == DecodeAs::kBgr) {
    if (color & PNG_COLOR_MASK_COLOR) png_set_bgr(r.png);
    else png_set_gray_to_rgb(r.png);
  } else {
    png_set_rgb_to_gray(r.png, 1, 0.299, 0.587);
  }
  png_set_interlace_handling(r.png);
  png_read_update_info(r.png, r.info);
  const int channels = as == DecodeAs::kBgr ? 3 : 1;
  if (png_get_rowbytes(r.png, r.info) != static_cast<size_t>(width) * static_cast<size_t>(channels) * (keep16 ? 2u : 1u))
    png_error(r.png, "unexpected row size after the colour conversions");
  c.image.create(static_cast<int>(height), static_cast<int>(width), keep16 ? CV_16UC1 : CV_8UC(channels));
  c.rows.resize(height);
  for (png_uint_32 y = 0; y < height; ++y) c.rows[y] = c.image.ptr<png_byte>(static_cast<int>(y));
  png_read_image(r.png, c.rows.data());
  png_read_end(r.png, nullptr);
  return true;
}

Result<cv::Mat> decode_png(std::span<const uint8_t> bytes, DecodeAs as, const std::string& what, uint64_t max_pixels) {
  auto c = std::make_unique<PngContext>();
  c->in = bytes;
  PngRead r;
  r.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, c.get(), png_on_error, png_on_warning);
  if (r.png) r.info = png_create_info_struct(r.png);
  if (!r.png || !r.info) return Error{what + ": cannot start the PNG decoder (out of memory)"};
  png_set_user_limits(r.png, 0x7fffffff, 0x7fffffff);  // the pixel count is checked below
  std::string limit_error;
  if (!png_decode_into(*c, r, as, max_pixels, limit_error)) return Error{what + ": not a readable PNG: " + c->message};
  if (!limit_error.empty()) return Error{what + ": " + limit_error};
  return std::move(c->image);
}

bool png_encode_into(PngContext& c, PngWrite& w, const cv::Mat& image) {
  if (setjmp(c.jump)) return false;
  png_set_write_fn(w.png, &c, png_write_bytes, png_flush_nothing);
  // OpenCV's defaults when no compression level is given: tuned for speed.
  png_set_filter(w.png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
  png_set_compression_level(w.png, Z_BEST_SPEED);
  png_set_compression_strategy(w.png, Z_RLE);
  const int channels = image.channels();
  png_set_IHDR(w.png, w.info, static_cast<png_uint_32>(image.cols), static_cast<png_uint_32>(image.rows),
               image.depth() == CV_16U ? 16 : 8,
               channels == 1 ? PNG_COLOR_TYPE_GRAY : channels == 3 ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_RGBA,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_BASE, PNG_FILTER_TYPE_BASE);
  png_write_info(w.png, w.info);
  png_set_bgr(w.png);
  png_set_swap(w.png);  // little-endian host: 16-bit samples are written big-endian
  c.rows.resize(static_cast<size_t>(image.rows));
  for (int y = 0; y < image.rows; ++y) c.rows[static_cast<size_t>(y)] = const_cast<png_bytep>(image.ptr<png_byte>(y));
  png_write_image(w.png, c.rows.data());
  png_write_end(w.png, nullptr);
  return true;
}

// ---------------------------------------------------------------- JPEG

struct JpegError {
  jpeg_error_mgr mgr;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX] = {};
};

void jpeg_on_error(j_common_ptr j) {
  auto* e = reinterpret_cast<JpegError*>(j->err);
  (*j->err->format_message)(j, e->message);
  std::longjmp(e->jump, 1);
}
void jpeg_on_message(j_common_ptr, int) {}  // warnings (corrupt data recovered) stay quiet, as in OpenCV

struct JpegDecodeContext {
  JpegError err;
  jpeg_decompress_struct d{};
  bool created = false;
  cv::Mat image;
  std::string limit_error;
  ~JpegDecodeContext() {
    if (created) jpeg_destroy_decompress(&d);
  }
};

bool jpeg_decode_into(JpegDecodeContext& c, std::span<const uint8_t> bytes, DecodeAs as, uint64_t max_pixels) {
  if (setjmp(c.err.jump)) return false;
  jpeg_create_decompress(&c.d);
  c.created = true;
  jpeg_mem_src(&c.d, bytes.data(), static_cast<unsigned long>(bytes.size()));
  jpeg_read_header(&c.d, TRUE);
  if (static_cast<uint64_t>(c.d.image_width) * c.d.image_height > max_pixels) {
    c.limit_error = "the image is " + std::to_string(c.d.image_height) + " x " + std::to_string(c.d.image_width) +
                    ", more than " + std::to_string(max_pixels) + " pixels";
    return true;
  }
  if (c.d.num_components == 4) {
    c.limit_error = "a four-component (CMYK or YCCK) JPEG, which this reader does not convert";
    return true;
  }
  const int channels = as == DecodeAs::kBgr ? 3 : 1;
  c.d.out_color_space = channels == 3 ? JCS_EXT_BGR : JCS_GRAYSCALE;
  jpeg_start_decompress(&c.d);
  if (c.d.output_components != channels) {
    c.limit_error = "the decoder gives " + std::to_string(c.d.output_components) + " channels, not " +
                    std::to_string(channels);
    jpeg_abort_decompress(&c.d);
    return true;
  }
  c.image.create(static_cast<int>(c.d.output_height), static_cast<int>(c.d.output_width), CV_8UC(channels));
  while (c.d.output_scanline < c.d.output_height) {
    JSAMPROW row = c.image.ptr<JSAMPLE>(static_cast<int>(c.d.output_scanline));
    jpeg_read_scanlines(&c.d, &row, 1);
  }
  jpeg_finish_decompress(&c.d);
  return true;
}

Result<cv::Mat> decode_jpeg(std::span<const uint8_t> bytes, DecodeAs as, const std::string& what, uint64_t max_pixels) {
  auto c = std::make_unique<JpegDecodeContext>();
  c->d.err = jpeg_std_error(&c->err.mgr);
  c->err.mgr.error_exit = jpeg_on_error;
  c->err.mgr.emit_message = jpeg_on_message;
  if (!jpeg_decode_into(*c, bytes, as, max_pixels)) return Error{what + ": not a readable JPEG: " + c->err.message};
  if (!c->limit_error.empty()) return Error{what + ": " + c->limit_error};
  return std::move(c->image);
}

struct JpegEncodeContext {
  JpegError err;
  jpeg_compress_struct e{};
  bool created = false;
  unsigned char* buffer = nullptr;
  unsigned long size = 0;
  ~JpegEncodeContext() {
    if (created) jpeg_destroy_compress(&e);
    std::free(buffer);
  }
};

bool jpeg_encode_into(JpegEncodeContext& c, const cv::Mat& image, int quality) {
  if (setjmp(c.err.jump)) return false;
  jpeg_create_compress(&c.e);
  c.created = true;
  jpeg_mem_dest(&c.e, &c.buffer, &c.size);
  c.e.image_width = static_cast<JDIMENSION>(image.cols);
  c.e.image_height = static_cast<JDIMENSION>(image.rows);
  c.e.input_components = image.channels();
  c.e.in_color_space = image.channels() == 3 ? JCS_EXT_BGR : JCS_GRAYSCALE;
  jpeg_set_defaults(&c.e);
  c.e.restart_interval = 0;
  jpeg_set_quality(&c.e, quality, TRUE);  // baseline tables, as OpenCV asks
  jpeg_start_compress(&c.e, TRUE);
  while (c.e.next_scanline < c.e.image_height) {
    JSAMPROW row = const_cast<JSAMPROW>(image.ptr<JSAMPLE>(static_cast<int>(c.e.next_scanline)));
    jpeg_write_scanlines(&c.e, &row, 1);
  }
  jpeg_finish_compress(&c.e);
  return true;
}

Status write_file(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) return Error{"cannot write '" + path + "': cannot open it for writing"};
  f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  f.close();
  if (!f) return Error{"cannot write '" + path + "' (disk full?)"};
  return Status::Ok();
}

}  // namespace

Result<cv::Mat> decode_image(std::span<const uint8_t> bytes, DecodeAs as, const std::string& what, uint64_t max_pixels) {
  if (is_png(bytes)) return decode_png(bytes, as, what, max_pixels);
  if (is_jpeg(bytes)) return decode_jpeg(bytes, as, what, max_pixels);
  return Error{what + ": neither a PNG nor a JPEG image (no signature)"};
}

Result<std::vector<uint8_t>> encode_png(const cv::Mat& image) {
  const int ch = image.channels();
  const bool ok8 = image.depth() == CV_8U && (ch == 1 || ch == 3 || ch == 4);
  const bool ok16 = image.depth() == CV_16U && ch == 1;
  if (image.empty() || !(ok8 || ok16))
    return Error{"PNG: cannot encode a " + std::to_string(image.rows) + " x " + std::to_string(image.cols) +
                 " image of type " + std::to_string(image.type()) + " (8-bit 1/3/4 channels or 16-bit gray)"};
  auto c = std::make_unique<PngContext>();
  PngWrite w;
  w.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, c.get(), png_on_error, png_on_warning);
  if (w.png) w.info = png_create_info_struct(w.png);
  if (!w.png || !w.info) return Error{"PNG: cannot start the encoder (out of memory)"};
  if (!png_encode_into(*c, w, image)) return Error{"PNG: encoding failed: " + c->message};
  return std::move(c->out);
}

Result<std::vector<uint8_t>> encode_jpeg(const cv::Mat& image, int quality) {
  if (image.empty() || image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3))
    return Error{"JPEG: cannot encode an image of type " + std::to_string(image.type()) + " (8-bit gray or BGR)"};
  if (quality < 1 || quality > 100) return Error{"JPEG: quality " + std::to_string(quality) + " is outside 1..100"};
  auto c = std::make_unique<JpegEncodeContext>();
  c->e.err = jpeg_std_error(&c->err.mgr);
  c->err.mgr.error_exit = jpeg_on_error;
  c->err.mgr.emit_message = jpeg_on_message;
  if (!jpeg_encode_into(*c, image, quality)) return Error{std::string("JPEG: encoding failed: ") + c->err.message};
  return std::vector<uint8_t>(c->buffer, c->buffer + c->size);
}

Status write_png(const std::string& path, const cv::Mat& image) {
  auto bytes = encode_png(image);
  if (!bytes) return Error{"cannot write '" + path + "': " + bytes.error().message};
  return write_file(path, *bytes);
}

Status write_jpeg(const std::string& path, const cv::Mat& image, int quality) {
  auto bytes = encode_jpeg(image, quality);
  if (!bytes) return Error{"cannot write '" + path + "': " + bytes.error().message};
  return write_file(path, *bytes);
}

Result<cv::Mat> read_image(const std::string& path, DecodeAs as, uint64_t max_pixels) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return Error{path + ": cannot open it"};
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  return decode_image(bytes, as, path, max_pixels);
}

}  // namespace orthosonar::codec
