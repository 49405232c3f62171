#pragma once
// One zstd frame decompressed in one call, with a decompression context per thread that is
// reused (ZSTD_decompress makes and frees one per call). Shared by the MCAP chunk reader
// (mcap_chunks.cpp) and the keyframe sweep's fusion cache (replay/run/sweep_store.cpp).
#include <cstddef>
#include <cstdint>

#include "core/result.hpp"

namespace orthosonar::replay::mcap {

// Decompresses the frame src[0, n) into dst[0, capacity): the number of bytes written, or
// zstd's error name (a frame larger than capacity is an error).
Result<size_t> zstd_decompress(const uint8_t* src, size_t n, uint8_t* dst, size_t capacity);

}  // namespace orthosonar::replay::mcap
