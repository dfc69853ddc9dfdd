// PNG files of rendered images: the renderer's encoding (render/image.h) written atomically.
#pragma once

#include <string>

#include "render/image.h"

namespace pd {

// Writes the PNG atomically (write_file_atomic); throws IoError on failure.
void write_png(const std::string& path, const ImageRGB8& image);

}  // namespace pd
