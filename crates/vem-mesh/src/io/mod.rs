//! File input and output: Gmsh `.msh` 4.1 input, VTK `.vtu` and SVG output, atomic writes.
