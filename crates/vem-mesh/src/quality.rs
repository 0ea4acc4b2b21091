//! Shape-regularity figures of assumption A1 (spec section 2) per element and per mesh.
