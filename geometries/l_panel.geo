// L-shaped panel: a square 100 mm x 100 mm without its lower right quarter,
// the re-entrant corner at (50, 50) mm rounded with a radius of 1 mm. Held at
// the foot of its upright arm (y = 0) and lifted at the end of its other
// arm, on the last 6 mm of that arm's lower face (l_panel.toml). After the
// L-shaped panel of Winkler, Hofstetter and Niederwanger (2001), scaled.
// Built-in kernel. Units: mm.
// Boundary sets from pd-mesh: left, bottom (the foot), right (the arm's
// end), top; "load" names the lifted part of the arm's lower face.
L = 100; r = 1; x_load = 94;
Point(1) = {0, 0, 0};
Point(2) = {L/2, 0, 0};
Point(3) = {L/2, L/2 - r, 0};
Point(4) = {L/2 + r, L/2 - r, 0};  // centre of the fillet
Point(5) = {L/2 + r, L/2, 0};
Point(6) = {x_load, L/2, 0};
Point(7) = {L, L/2, 0};
Point(8) = {L, L, 0};
Point(9) = {0, L, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Circle(3) = {3, 4, 5};
Line(4) = {5, 6};
Line(5) = {6, 7};
Line(6) = {7, 8};
Line(7) = {8, 9};
Line(8) = {9, 1};
Curve Loop(1) = {1:8};
Plane Surface(1) = {1};
Physical Curve("load") = {5};
