// The quarter of the paper's 110 × 110 mm rig specimen (docs/theory.md §6) written as data: the mesh of
// tricot's built-in rig ([mesh] nx = 12, ny = 10, grading = grading_x = 0.5, element Q8) as a Gmsh
// geometry. The built-in generator places its element boundaries in a geometric progression whose first
// (at x = 0, y = 0) over last element size is the grading; the same arithmetic here puts a point at each,
// one element per line, so that both meshes have the same nodes (the corners to round-off, the mid-side
// nodes that Gmsh places to 1e-12 of the side).
W = 55;   // mm, half the specimen's side
H = 55;
nx = 12;  // elements across and along
ny = 10;
g = 0.5;  // first over last element size, both ways

// Levels: sizes 1, r, r², … summed, then scaled to the side.
rx = g^(-1 / (nx - 1));
sum = 0; h = 1;
For i In {0 : nx - 1}
  x[i] = sum; sum += h; h *= rx;
EndFor
x[nx] = sum;
f = W / sum;
For i In {0 : nx - 1}
  x[i] = x[i] * f;
EndFor
x[nx] = W;
ry = g^(-1 / (ny - 1));
sum = 0; h = 1;
For j In {0 : ny - 1}
  y[j] = sum; sum += h; h *= ry;
EndFor
y[ny] = sum;
f = H / sum;
For j In {0 : ny - 1}
  y[j] = y[j] * f;
EndFor
y[ny] = H;

// The boundary, counter-clockwise from the centre (0, 0): bottom, right, top, left; a point per level.
p = newp;
For i In {0 : nx}
  Point(p + i) = {x[i], 0, 0};              // bottom: p … p + nx
EndFor
For j In {1 : ny}
  Point(p + nx + j) = {W, y[j], 0};         // right: … p + nx + ny (the corner W, H)
EndFor
For i In {1 : nx}
  Point(p + nx + ny + i) = {x[nx - i], H, 0};  // top, from x = W back to 0
EndFor
For j In {1 : ny - 1}
  Point(p + 2 * nx + ny + j) = {0, y[ny - j], 0};  // left, from H down
EndFor
n = 2 * (nx + ny);  // points around
For k In {0 : n - 1}
  Line(k + 1) = {p + k, p + (k + 1) % n};
  Transfinite Curve{k + 1} = 2;  // one element per line
EndFor
Curve Loop(1) = {1 : n};
Plane Surface(1) = {1};
Transfinite Surface{1} = {p, p + nx, p + nx + ny, p + 2 * nx + ny};
Recombine Surface{1};

Physical Surface("knit") = {1};
Physical Curve("bottom") = {1 : nx};
Physical Curve("right") = {nx + 1 : nx + ny};
Physical Curve("top") = {nx + ny + 1 : 2 * nx + ny};
Physical Curve("left") = {2 * nx + ny + 1 : n};
