#include "shared/codec/zstd_codec.h"

#include <zstd.h>

namespace fleetmap {

std::string ZstdCompress(const void* data, size_t size, int level) {
  std::string out(ZSTD_compressBound(size), '\0');
  const size_t written = ZSTD_compress(out.data(), out.size(), data, size, level);
  // Compressing into a buffer of compressBound bytes cannot fail for valid levels.
  if (ZSTD_isError(written)) return std::string();
  out.resize(written);
  // Frames are often kept (stored grids, packed submaps): give back the bound's spare capacity.
  out.shrink_to_fit();
  return out;
}

bool ZstdDecompress(const std::string& compressed, size_t expected_size, std::string* out,
                    std::string* error) {
  const unsigned long long declared =
      ZSTD_getFrameContentSize(compressed.data(), compressed.size());
  if (declared == ZSTD_CONTENTSIZE_ERROR) {
    *error = "not a zstd frame";
    return false;
  }
  if (declared == ZSTD_CONTENTSIZE_UNKNOWN) {
    *error = "zstd frame does not declare its content size";
    return false;
  }
  if (declared != expected_size) {
    *error = "zstd frame holds " + std::to_string(declared) + " bytes, expected " +
             std::to_string(expected_size);
    return false;
  }
  out->assign(expected_size, '\0');
  const size_t written =
      ZSTD_decompress(out->data(), out->size(), compressed.data(), compressed.size());
  if (ZSTD_isError(written)) {
    *error = std::string("corrupt zstd data: ") + ZSTD_getErrorName(written);
    return false;
  }
  if (written != expected_size) {
    *error = "zstd frame decompressed to " + std::to_string(written) + " bytes, expected " +
             std::to_string(expected_size);
    return false;
  }
  return true;
}

}  // namespace fleetmap
