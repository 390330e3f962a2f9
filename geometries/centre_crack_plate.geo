// Square steel plate 500 mm x 500 mm for the centre-crack opening study
// (docs/validation.md, "Crack opening"): the crack itself, 100 mm long at
// mid-height, is a pre-crack of the scene (centre_crack_plate.toml), and the
// FEM reference adds it to the same plate as two faces. Built-in kernel. Units: mm.
// Boundary sets from pd-mesh: left, right, bottom, top.
L = 500;
Point(1) = {0, 0, 0};
Point(2) = {L, 0, 0};
Point(3) = {L, L, 0};
Point(4) = {0, L, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
