//! Pictures made of numbers, knowing nothing of scenes: 8-bit sRGB images, the false-colour
//! scale (linear or logarithmic, round automatic ranges, bands), isolines (marching squares),
//! a built-in bitmap font for legends and labels, legends, and tone mapping of luminance images
//! for the adapted eye (Ward Larson, Rushmeier & Piatko 1997 histogram adjustment).
