// Square glass plate 50 mm x 50 mm with a hole of radius 5 mm centred at
// (25, 30) mm and, 10 mm below the hole's centre, a 15 mm pre-crack from the
// left edge (a [[precracks]] entry of hole_plate.toml): the case with a hole
// of docs/refinement.md, where a coarse grid's staircase hole boundary may
// crack on its own. Built-in kernel. Units: mm.
// Boundary sets from pd-mesh: left, right, bottom, top, hole_1.
W = 50; H = 50; R = 5; XC = 25; YC = 30;
Point(1) = {0, 0, 0};
Point(2) = {W, 0, 0};
Point(3) = {W, H, 0};
Point(4) = {0, H, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};

Point(5) = {XC, YC, 0};
Point(6) = {XC + R, YC, 0};
Point(7) = {XC, YC + R, 0};
Point(8) = {XC - R, YC, 0};
Point(9) = {XC, YC - R, 0};
Circle(5) = {6, 5, 7};
Circle(6) = {7, 5, 8};
Circle(7) = {8, 5, 9};
Circle(8) = {9, 5, 6};
Curve Loop(2) = {5, 6, 7, 8};

Plane Surface(1) = {1, 2};
