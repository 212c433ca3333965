// A cruciform biaxial specimen of knit, 120 × 120 mm: a 40 mm central square with four 40 mm arms,
// the re-entrant corners rounded (radius 6 mm) as cruciform specimens are cut. Lengths in mm; the
// mesh frame's origin is the centre. The arms' ends are the grips, named by their compass side; the
// mesh is finer at the fillets, where the arms meet (2.5 mm there, [mesh] size elsewhere).
w = 20;   // half the arm's width
L = 60;   // the grip line's distance from the centre
r = 10;   // fillet radius
lc = 4;   // the size away from the fillets (the project's [mesh] size caps it)
lf = 2.5; // at the fillets

Point(1) = {L, -w, 0, lc};      Point(2) = {L, w, 0, lc};
Point(3) = {w + r, w, 0, lf};   Point(4) = {w + r, w + r, 0, lf};   Point(5) = {w, w + r, 0, lf};
Point(6) = {w, L, 0, lc};       Point(7) = {-w, L, 0, lc};
Point(8) = {-w, w + r, 0, lf};  Point(9) = {-w - r, w + r, 0, lf};  Point(10) = {-w - r, w, 0, lf};
Point(11) = {-L, w, 0, lc};     Point(12) = {-L, -w, 0, lc};
Point(13) = {-w - r, -w, 0, lf}; Point(14) = {-w - r, -w - r, 0, lf}; Point(15) = {-w, -w - r, 0, lf};
Point(16) = {-w, -L, 0, lc};    Point(17) = {w, -L, 0, lc};
Point(18) = {w, -w - r, 0, lf}; Point(19) = {w + r, -w - r, 0, lf}; Point(20) = {w + r, -w, 0, lf};

Line(1) = {1, 2};          // east grip
Line(2) = {2, 3};
Circle(3) = {3, 4, 5};
Line(4) = {5, 6};
Line(5) = {6, 7};          // north grip
Line(6) = {7, 8};
Circle(7) = {8, 9, 10};
Line(8) = {10, 11};
Line(9) = {11, 12};        // west grip
Line(10) = {12, 13};
Circle(11) = {13, 14, 15};
Line(12) = {15, 16};
Line(13) = {16, 17};       // south grip
Line(14) = {17, 18};
Circle(15) = {18, 19, 20};
Line(16) = {20, 1};

Curve Loop(1) = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16};
Plane Surface(1) = {1};
Physical Surface("knit") = {1};
Physical Curve("east") = {1};
Physical Curve("north") = {5};
Physical Curve("west") = {9};
Physical Curve("south") = {13};
