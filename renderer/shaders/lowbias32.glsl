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
