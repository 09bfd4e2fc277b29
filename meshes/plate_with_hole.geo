// Unstructured all-quadrilateral mesh of a plate [0, width] x [0, height] (mm) with a
// central circular hole of the given radius; target element size `size` (mm).
// Frontal-Delaunay triangulation recombined into quadrilaterals by the Blossom algorithm.
// (Algorithm 8, frontal-Delaunay for quads, crashes the gmsh 4.8 of Debian 12.)
// Boundary curves are tagged bottom (1), right (2), top (3), left (4), hole (5); the
// surface fabric (10). Uniform refinement (each quad split into four, new boundary nodes on
// the circle) is done by the caller: fabric_dolfinx.mesh.plate_with_hole(refinements=...).
DefineConstant[
  width = {50, Name "Parameters/width (mm)"}
  height = {50, Name "Parameters/height (mm)"}
  radius = {10, Name "Parameters/hole radius (mm)"}
  size = {5, Name "Parameters/element size (mm)"}
];
cx = width / 2;
cy = height / 2;
Point(1) = {0, 0, 0, size};
Point(2) = {width, 0, 0, size};
Point(3) = {width, height, 0, size};
Point(4) = {0, height, 0, size};
Point(5) = {cx, cy, 0, size};
Point(6) = {cx + radius, cy, 0, size};
Point(7) = {cx, cy + radius, 0, size};
Point(8) = {cx - radius, cy, 0, size};
Point(9) = {cx, cy - radius, 0, size};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Circle(5) = {6, 5, 7};
Circle(6) = {7, 5, 8};
Circle(7) = {8, 5, 9};
Circle(8) = {9, 5, 6};
Curve Loop(1) = {1, 2, 3, 4};
Curve Loop(2) = {5, 6, 7, 8};
Plane Surface(1) = {1, 2};
Physical Curve("bottom", 1) = {1};
Physical Curve("right", 2) = {2};
Physical Curve("top", 3) = {3};
Physical Curve("left", 4) = {4};
Physical Curve("hole", 5) = {5, 6, 7, 8};
Physical Surface("fabric", 10) = {1};
Mesh.Algorithm = 6;
Mesh.RecombinationAlgorithm = 1;
Mesh.RecombineAll = 1;
