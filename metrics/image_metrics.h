#pragma once
// Full-reference image quality metrics on CPU images: luma, PSNR and SSIM.
// Definitions (weights, constants, window, averaging) are written down in
// docs/analysis.md; SSIM follows Wang, Bovik, Sheikh, Simoncelli 2004,
// "Image quality assessment: from error visibility to structural similarity",
// IEEE TIP 13(4), and their reference MATLAB code ssim_index.m.
//
// Colour inputs are expected to hold sRGB-encoded values in [0, 1]; the
// metrics work on those encoded values, as the reference code does on 8-bit
// images. Accepted channel counts are 1 (grey), 3 (RGB) and 4 (RGBA).
#include "core/image.h"

namespace fovlab::metrics {

// Luma with ITU-R BT.601 weights (0.299 R + 0.587 G + 0.114 B) applied to the
// encoded values, as MATLAB's rgb2gray. Alpha is ignored. A grey image is
// returned unchanged. Throws std::invalid_argument for other channel counts
// or a pixel buffer that does not match width * height * channels.
Image luma(const Image& image);

struct PsnrResult {
  double mse = 0.0;        // mean squared error over every colour sample
  double psnr_db = 0.0;    // 10 log10(1 / mse); +infinity when identical
  bool identical = false;  // mse == 0: every colour sample is bit-equal in value
};

// PSNR with peak value 1.0 over the colour channels (R, G, B; alpha ignored;
// the single channel of a grey image). RGB and RGBA images may be compared
// with each other; grey against colour may not. Throws std::invalid_argument
// for mismatched sizes or colour channel counts, or empty images.
PsnrResult psnr(const Image& a, const Image& b);

struct SsimResult {
  double mean_ssim = 0.0;  // plain mean of `map`
  Image map;               // one channel, (width - 10) x (height - 10): local SSIM at each
                           // position where the 11x11 window lies fully inside the image
};

// Mean SSIM of the lumas of `a` and `b` (Wang et al. 2004): data range 1,
// K1 = 0.01, K2 = 0.03, 11x11 Gaussian window with sigma 1.5, 'valid' window
// positions only. Throws std::invalid_argument for mismatched sizes or images
// smaller than 11x11.
SsimResult ssim(const Image& a, const Image& b);

}  // namespace fovlab::metrics
