// Structured quadrilateral patch [0, width] x [0, height] (mm) with nx x ny elements.
// Boundary curves are tagged bottom (1), right (2), top (3), left (4); the surface fabric (10).
// Parameters: gmsh -setnumber width 50 -setnumber nx 10 ... rectangle.geo -2
DefineConstant[
  width = {50, Name "Parameters/width (mm)"}
  height = {50, Name "Parameters/height (mm)"}
  nx = {10, Name "Parameters/elements along x"}
  ny = {10, Name "Parameters/elements along y"}
];
Point(1) = {0, 0, 0};
Point(2) = {width, 0, 0};
Point(3) = {width, height, 0};
Point(4) = {0, height, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = nx + 1;
Transfinite Curve{2, 4} = ny + 1;
Transfinite Surface{1};
Recombine Surface{1};
Physical Curve("bottom", 1) = {1};
Physical Curve("right", 2) = {2};
Physical Curve("top", 3) = {3};
Physical Curve("left", 4) = {4};
Physical Surface("fabric", 10) = {1};
