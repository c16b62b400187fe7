//! False-colour plans of a finished bake's working plane or of a planar node, with isolux
//! contours (`bake plan`).
