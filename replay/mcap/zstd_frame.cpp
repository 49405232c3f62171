#include "replay/mcap/zstd_frame.hpp"

#include <zstd.h>

#include <memory>
#include <string>

namespace orthosonar::replay::mcap {

Result<size_t> zstd_decompress(const uint8_t* src, size_t n, uint8_t* dst, size_t capacity) {
  struct FreeDCtx {
    void operator()(ZSTD_DCtx* d) const { ZSTD_freeDCtx(d); }
  };
  thread_local std::unique_ptr<ZSTD_DCtx, FreeDCtx> dctx(ZSTD_createDCtx());
  const size_t r = dctx ? ZSTD_decompressDCtx(dctx.get(), dst, capacity, src, n) : ZSTD_decompress(dst, capacity, src, n);
  if (ZSTD_isError(r)) return Error{ZSTD_getErrorName(r)};
  return r;
}

}  // namespace orthosonar::replay::mcap
