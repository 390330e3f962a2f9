// Kalthoff-Winkler plate: a steel plate 100 mm wide and 200 mm tall with two
// parallel edge notches from its left side, 50 mm long and 1.5 mm wide with
// half-circle tips, 50 mm apart (at y = 75 and 125 mm); the left edge
// between them is struck (kalthoff_winkler.toml). After Kalthoff and
// Winkler (1988). Built-in kernel. Units: mm.
// Boundary sets from pd-mesh: left (the three parts of the left side),
// right, bottom, top; "impact" names the struck part of the left edge
// between the notches, "notches" their faces.
W = 100; H = 200; a = 50; w = 1.5; y1 = 75; y2 = 125;
Point(1) = {0, 0, 0};
Point(2) = {W, 0, 0};
Point(3) = {W, H, 0};
Point(4) = {0, H, 0};
// Upper notch, entered from above.
Point(5) = {0, y2 + w/2, 0};
Point(6) = {a - w/2, y2 + w/2, 0};
Point(7) = {a - w/2, y2, 0};
Point(8) = {a, y2, 0};
Point(9) = {a - w/2, y2 - w/2, 0};
Point(10) = {0, y2 - w/2, 0};
// Lower notch.
Point(11) = {0, y1 + w/2, 0};
Point(12) = {a - w/2, y1 + w/2, 0};
Point(13) = {a - w/2, y1, 0};
Point(14) = {a, y1, 0};
Point(15) = {a - w/2, y1 - w/2, 0};
Point(16) = {0, y1 - w/2, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 6};
Circle(6) = {6, 7, 8};
Circle(7) = {8, 7, 9};
Line(8) = {9, 10};
Line(9) = {10, 11};  // the struck edge
Line(10) = {11, 12};
Circle(11) = {12, 13, 14};
Circle(12) = {14, 13, 15};
Line(13) = {15, 16};
Line(14) = {16, 1};
Curve Loop(1) = {1:14};
Plane Surface(1) = {1};
Physical Curve("impact") = {9};
Physical Curve("notches") = {5, 6, 7, 8, 10, 11, 12, 13};
