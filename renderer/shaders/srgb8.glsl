// The sRGB8 encoding of what a participant sees (shared by srgb8_encode and zone_band):
// core/colour.cpp's encode_srgb, then rounded to the nearest of 256 levels; NaN shows black, values
// are clipped to [0, 1].

uint srgb8(float linear) {
  float value = clamp(isnan(linear) ? 0.0 : linear, 0.0, 1.0);
  float encoded = value <= 0.0031308 ? 12.92 * value : 1.055 * pow(value, 1.0 / 2.4) - 0.055;
  return uint(floor(encoded * 255.0 + 0.5));
}

// RGBA8 packed in one uint, alpha 255.
uint packed_srgb8(vec4 colour) {
  return srgb8(colour.r) | (srgb8(colour.g) << 8) | (srgb8(colour.b) << 16) | (255u << 24);
}
