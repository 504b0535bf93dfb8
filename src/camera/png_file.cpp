#include "rov_tether/camera/png_file.hpp"

#include <png.h>

#include <csetjmp>
#include <cstdio>

namespace rov_tether::camera
{
namespace
{

/// The rows of `image` into the open `file`; false on any libpng error (reported through setjmp). Only plain
/// data lives between setjmp and a longjmp back to it.
bool writeRows(std::FILE* file, const cv::Mat& image, int bit_depth, int colour_type)
{
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
  if (info == nullptr)
  {
    png_destroy_write_struct(&png, nullptr);
    return false;
  }
  if (setjmp(png_jmpbuf(png)))
  {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_init_io(png, file);
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.cols), static_cast<png_uint_32>(image.rows), bit_depth,
               colour_type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_compression_level(png, 1);  // fast, as OpenCV's default
  png_write_info(png, info);
  if (colour_type == PNG_COLOR_TYPE_RGB)
  {
    png_set_bgr(png);
  }
  if (bit_depth == 16)
  {
    png_set_swap(png);  // PNG's 16-bit samples are big-endian; the host's are little-endian
  }
  for (int r = 0; r < image.rows; ++r)
  {
    png_write_row(png, image.ptr<png_byte>(r));
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

}  // namespace

bool writePng(const std::string& path, const cv::Mat& image)
{
  int bit_depth = 8;
  int colour_type = PNG_COLOR_TYPE_GRAY;
  switch (image.type())
  {
    case CV_8UC1:
      break;
    case CV_16UC1:
      bit_depth = 16;
      break;
    case CV_8UC3:
      colour_type = PNG_COLOR_TYPE_RGB;
      break;
    default:
      return false;
  }
  if (image.empty())
  {
    return false;
  }
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr)
  {
    return false;
  }
  const bool written = writeRows(file, image, bit_depth, colour_type);
  return std::fclose(file) == 0 && written;
}

}  // namespace rov_tether::camera
