//! Mesh file formats (Triangle .node/.ele, Gmsh .msh 4.1, VTK .vtu, Wavefront .obj).
//! Writers go through a temp file and rename so a failure never leaves a partial file.
