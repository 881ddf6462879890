#pragma once
// LDR-FLIP, the image difference evaluator of Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström
// and Fairchild, "FLIP: A Difference Evaluator for Alternating Images", Proc. ACM Comput. Graph.
// Interact. Tech. 3(2), article 15, 2020 (https://doi.org/10.1145/3406183), with the erratum
// published on research.nvidia.com (the achromatic channel of the feature pipeline is normalised
// by division by 116). Our own implementation in double precision; the constants, the order of
// operations and the kernels were checked against NVIDIA's reference code (github.com/NVlabs/flip,
// FLIP.h and flip_api.py). Definitions and checks: docs/analysis.md, section "FLIP".
//
// Inputs hold sRGB-encoded values in [0, 1], as the other metrics of this folder (and as
// LDR-FLIP itself expects).
#include "core/image.h"

namespace fovlab::metrics {

struct FlipResult {
  double mean_flip = 0.0;  // plain mean of the per-pixel FLIP error, in [0, 1]; 0 for identical images
  Image error_map;         // one channel, the size of the inputs: per-pixel FLIP error in [0, 1]
};

// LDR-FLIP of `test` against `reference` seen at `pixels_per_degree` pixels per degree of visual
// angle (the FLIP tool's default, a 0.7 m wide 3840-pixel monitor at 0.7 m, is about 67.02).
//
// Accepted layouts: RGB and RGBA (alpha ignored; RGB may be compared with RGBA), or grey against
// grey (the grey value is used for R, G and B). Throws std::invalid_argument for mismatched sizes,
// grey against colour, other channel counts, a pixel buffer that does not match width * height *
// channels, empty images, a colour sample outside [0, 1] (or NaN), or a pixels_per_degree that is
// not positive and finite.
FlipResult flip(const Image& reference, const Image& test, double pixels_per_degree);

// The paper's cmax: the HyAB distance, raised to qc = 0.7, between Hunt-adjusted green (0, 1, 0)
// and blue (0, 0, 1) of linear RGB: the largest colour difference, which maps to error 1.
// About 41.2761 (the value NVIDIA's CUDA code hard-codes).
double flip_cmax();

}  // namespace fovlab::metrics
