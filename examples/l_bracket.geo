// An L-shaped fabric part (mm): a vertical leg [0, 40] x [0, 120] and a horizontal leg
// [0, 120] x [0, 40]. Boundaries: top (y = 120, held), tip (x = 120, loaded), edges (the
// rest, free). One region, fabric. Unstructured, recombined into quadrilaterals.
DefineConstant[ size = {5, Min 1, Max 20, Name "Parameters/element size (mm)"} ];
Point(1) = {0, 0, 0, size};
Point(2) = {120, 0, 0, size};
Point(3) = {120, 40, 0, size};
Point(4) = {40, 40, 0, size};
Point(5) = {40, 120, 0, size};
Point(6) = {0, 120, 0, size};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 6};
Line(6) = {6, 1};
Curve Loop(1) = {1, 2, 3, 4, 5, 6};
Plane Surface(1) = {1};
Physical Curve("tip") = {2};
Physical Curve("top") = {5};
Physical Curve("edges") = {1, 3, 4, 6};
Physical Surface("fabric") = {1};
Mesh.RecombineAll = 1;
