// The wheel of scenarios/wheel.toml meshed by Gmsh instead of softway's generator: an
// unstructured annulus from the 1 cm hub to the 10 cm rim, 288 nodes on the rim, 16 on the
// hub's circle, the element size growing by 0.15 of the distance from either circle
// (Frontal-Delaunay). Physical groups: "rim" (the rim's nodes, for the contact), "hub" and
// "body". Make the mesh shipped beside it with
//   gmsh -2 -format msh41 meshes/wheel-hub-288.geo -o meshes/wheel-hub-288.msh
// or python3 meshes/make.py (meshes/README.md).
SetFactory("Built-in");
R = 0.1;       // m, rim radius
rh = 0.01;     // m, hub radius
n_rim = 288;   // nodes on the rim
n_hub = 16;    // nodes on the hub's circle
grow = 0.15;   // size growth per unit distance from the circles

Point(1) = {0, 0, 0};
Point(2) = {R, 0, 0};   Point(3) = {0, R, 0};   Point(4) = {-R, 0, 0};   Point(5) = {0, -R, 0};
Point(6) = {rh, 0, 0};  Point(7) = {0, rh, 0};  Point(8) = {-rh, 0, 0};  Point(9) = {0, -rh, 0};
Circle(1) = {2, 1, 3};  Circle(2) = {3, 1, 4};  Circle(3) = {4, 1, 5};  Circle(4) = {5, 1, 2};
Circle(5) = {6, 1, 7};  Circle(6) = {7, 1, 8};  Circle(7) = {8, 1, 9};  Circle(8) = {9, 1, 6};
Transfinite Curve {1, 2, 3, 4} = n_rim / 4 + 1;
Transfinite Curve {5, 6, 7, 8} = n_hub / 4 + 1;
Curve Loop(1) = {1, 2, 3, 4};
Curve Loop(2) = {5, 6, 7, 8};
Plane Surface(1) = {1, 2};

h_rim = 2 * Pi * R / n_rim;
h_hub = 2 * Pi * rh / n_hub;
Field[1] = Distance;
Field[1].CurvesList = {1, 2, 3, 4};
Field[1].Sampling = 1000;
Field[2] = MathEval;
Field[2].F = Sprintf("%.17g + %.17g * F1", h_rim, grow);
Field[3] = Distance;
Field[3].CurvesList = {5, 6, 7, 8};
Field[3].Sampling = 200;
Field[4] = MathEval;
Field[4].F = Sprintf("%.17g + %.17g * F3", h_hub, grow);
Field[5] = Min;
Field[5].FieldsList = {2, 4};
Background Field = 5;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm = 6;
Mesh.MshFileVersion = 4.1;

Physical Curve("rim") = {1, 2, 3, 4};
Physical Curve("hub") = {5, 6, 7, 8};
Physical Surface("body") = {1};
