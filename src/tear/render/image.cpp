#include "tear/render/image.h"

#include <png.h>

#include <csetjmp>
#include <cstring>
#include <memory>
#include <stdexcept>

namespace tear {

namespace {

// libpng reports errors through a longjmp back into the calling function; everything that
// function changes after its setjmp lives on the heap, so nothing is left indeterminate.
void on_error(png_structp png, png_const_charp message) {
  *static_cast<std::string*>(png_get_error_ptr(png)) = message;
  png_longjmp(png, 1);
}
void on_warning(png_structp, png_const_charp) {}

void write_bytes(png_structp png, png_bytep data, png_size_t n) {
  static_cast<std::string*>(png_get_io_ptr(png))->append(reinterpret_cast<const char*>(data), n);
}
void flush_nothing(png_structp) {}

struct Source {
  const std::string* bytes;
  size_t pos = 0;
};
void read_bytes(png_structp png, png_bytep out, png_size_t n) {
  Source* src = static_cast<Source*>(png_get_io_ptr(png));
  if (n > src->bytes->size() - src->pos) png_error(png, "truncated file");
  std::memcpy(out, src->bytes->data() + src->pos, n);
  src->pos += n;
}

struct Decoded {
  Image image;
  std::vector<png_bytep> rows;
};

}  // namespace

std::string encode_png(const Image& image) {
  if (image.width <= 0 || image.height <= 0) throw std::runtime_error("PNG: empty image");
  auto out = std::make_unique<std::string>();
  auto error = std::make_unique<std::string>();
  std::vector<png_bytep> rows(size_t(image.height));
  for (int y = 0; y < image.height; ++y) rows[size_t(y)] = const_cast<png_bytep>(image.at(0, y));
  png_structp png =
      png_create_write_struct(PNG_LIBPNG_VER_STRING, error.get(), on_error, on_warning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    throw std::runtime_error("PNG: out of memory");
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw std::runtime_error("PNG encoding failed: " + *error);
  }
  png_set_write_fn(png, out.get(), write_bytes, flush_nothing);
  png_set_IHDR(png, info, png_uint_32(image.width), png_uint_32(image.height), 8,
               PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_set_compression_level(png, 6);
  png_set_rows(png, info, rows.data());
  png_write_png(png, info, PNG_TRANSFORM_IDENTITY, nullptr);
  png_destroy_write_struct(&png, &info);
  return std::move(*out);
}

Image decode_png(const std::string& bytes) {
  if (bytes.size() < 8 || png_sig_cmp(reinterpret_cast<png_const_bytep>(bytes.data()), 0, 8))
    throw std::runtime_error("not a PNG file");
  auto error = std::make_unique<std::string>();
  auto src = std::make_unique<Source>(Source{&bytes});
  auto result = std::make_unique<Decoded>();
  png_structp png =
      png_create_read_struct(PNG_LIBPNG_VER_STRING, error.get(), on_error, on_warning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    throw std::runtime_error("PNG: out of memory");
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw std::runtime_error("PNG decoding failed: " + *error);
  }
  png_set_read_fn(png, src.get(), read_bytes);
  png_read_info(png, info);
  png_set_expand(png);
  png_set_strip_16(png);
  png_set_strip_alpha(png);
  png_set_gray_to_rgb(png);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  const png_uint_32 w = png_get_image_width(png, info), h = png_get_image_height(png, info);
  if (png_get_rowbytes(png, info) != size_t(w) * 3) png_error(png, "unexpected row layout");
  result->image = Image(int(w), int(h));
  result->rows.resize(h);
  for (png_uint_32 y = 0; y < h; ++y) result->rows[y] = result->image.at(0, int(y));
  png_read_image(png, result->rows.data());
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  return std::move(result->image);
}

const char* libpng_version() { return PNG_LIBPNG_VER_STRING; }

}  // namespace tear
