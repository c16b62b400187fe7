//! Luminance images of a finished bake seen through a pinhole camera (`bake view`).
