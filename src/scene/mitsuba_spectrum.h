// Mitsuba 3 colour values as linear sRGB: <rgb>, <spectrum> (one value, or wavelength:value
// pairs) and <float> given where a colour is expected. Private to src/scene (used by
// load_mitsuba.cpp).
//
// Mitsuba's RGB variants integrate a wavelength:value spectrum against the CIE 1931
// colour matching functions over the listed wavelengths only (values interpolated
// linearly between the listed points, nothing outside them) and convert XYZ to linear
// sRGB (https://mitsuba.readthedocs.io/en/stable/src/key_topics/scene_format.html,
// "Spectra"). Emitter spectra are radiance: unbounded, normalised so that Y is the mean
// of the values weighted by the luminous efficiency curve. Reflectance spectra are made
// relative to white: Mitsuba 3 weights them by the D65 illuminant so that a reflectance
// of 1 everywhere is sRGB (1, 1, 1); we divide each channel by that of the flat spectrum
// instead (no D65 table), which agrees for the smooth spectra of real materials, and
// clamp to [0, 1] as Mitsuba does.
#pragma once

#include <string>
#include <vector>

#include "core/math.h"

namespace multiray::detail {

// The CIE 1931 2-degree observer at `nm` nanometres, from the multi-lobe Gaussian fit of
// Wyman, Sloan and Shirley, "Simple Analytic Approximations to the CIE XYZ Color
// Matching Functions", JCGT 2(2), 2013 (within about 1% of the tabulated curves'
// integrals). Unnormalised: y peaks at about 1 near 555 nm.
Vec3 cie1931_xyz(double nm);

// Linear sRGB (D65 white) of CIE XYZ.
Vec3 xyz_to_linear_srgb(Vec3 xyz);

// A spectrum given as wavelength:value pairs, wavelengths strictly increasing (nm).
struct SampledSpectrum {
  std::vector<double> nm, value;
};

// Linear sRGB of `s` as an emitter's radiance: negative channels (out of gamut) become 0.
Vec3 radiance_spectrum_to_rgb(const SampledSpectrum& s);

// Linear sRGB of `s` as a reflectance, each channel in [0, 1].
Vec3 reflectance_spectrum_to_rgb(const SampledSpectrum& s);

// Parses Mitsuba's "400:0.343, 404:0.445, ..." into *out. Returns an empty string or one
// line saying what is wrong (a pair without ':', a non-number, wavelengths not increasing).
std::string parse_spectrum_pairs(const std::string& text, SampledSpectrum* out);

}  // namespace multiray::detail
