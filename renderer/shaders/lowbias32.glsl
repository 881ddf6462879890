// lowbias32 (Chris Wellons' integer hash): the shaders' stateless random numbers, a hash of what
// identifies a draw (seed, frame, pixel, sample, dimension), so the same inputs give the same bits.
// The CPU copy for reference tests is in foveation/foveation_mask.cpp.
uint lowbias32(uint x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

// A pixel's threshold in [0, 1) for a mask drawn with `seed` at `frame`: the top 24 bits of the
// chained hash, exact in float (foveation/foveation_mask.cpp mask_threshold is the CPU copy).
float pixel_threshold(uint seed, uint frame, uvec2 pixel) {
  uint h = lowbias32(pixel.x + lowbias32(pixel.y + lowbias32(frame + lowbias32(seed))));
  return float(h >> 8) * (1.0 / 16777216.0);
}
