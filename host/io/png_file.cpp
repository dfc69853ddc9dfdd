#include "host/io/png_file.h"

#include "host/io/atomic_file.h"

namespace pd {

void write_png(const std::string& path, const ImageRGB8& image) {
  write_file_atomic(path, encode_png(image));
}

}  // namespace pd
