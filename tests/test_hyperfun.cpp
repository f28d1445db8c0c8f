// HyperFun programs as FRep trees: each program below is written for the test from the
// language's manual, and its tree's values are compared point by point with HyperFun's
// definitions written out here by hand (the manual's formulas, alpha = 0 R-functions).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <string>

#include "base/errors.h"
#include "frep/hyperfun_import.h"
#include "frep/tree.h"

namespace frep {
namespace {

using Field = std::function<double(double, double, double)>;

Model load(const std::string& text) {
  return importHyperFun(text, "test.hf");
}

// The tree of `program` against `expected` at random points of [-range, range]^3.
void expectValues(const std::string& program, const Field& expected, double range = 3.0) {
  const Program p = compile(load(program).root);
  std::mt19937 g(11);
  std::uniform_real_distribution<double> u(-range, range);
  for (int i = 0; i < 300; ++i) {
    const double x = u(g), y = u(g), z = u(g);
    const double want = expected(x, y, z);
    ASSERT_NEAR(p.eval(x, y, z), want, 1e-9 * (1.0 + std::fabs(want)))
        << "at (" << x << ", " << y << ", " << z << ")\n"
        << program;
  }
}

std::string model(const std::string& body) {
  return "my_model(x[3], a[1])\n{\n" + body + "\n}\n";
}

double sq(double v) {
  return v * v;
}
double unite(double f, double g) {
  return f + g + std::sqrt(f * f + g * g);
}
double meet(double f, double g) {
  return f + g - std::sqrt(f * f + g * g);
}

std::string errorOf(const std::string& program) {
  try {
    load(program);
  } catch (const ModelError& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(HyperFun, ArithmeticFollowsItsInterpreter) {
  // unary minus binds before ^ ((-x)^2), ^ from the left, the set operators with + and -
  expectValues(model("my_model = 9 - x[1]^2 - x[2]^2 - x[3]^2;"),
               [](double x, double y, double z) { return 9 - x * x - y * y - z * z; });
  expectValues(model("my_model = -x[1]^2 + 2^3^2 - 1;"),
               [](double x, double, double) { return x * x + 64 - 1; });
  expectValues(model("my_model = 4 - x[1]*x[1] / 2 - abs(x[2]) * 3 + 1/(2 + x[3]*x[3]);"),
               [](double x, double y, double z) {
                 return 4 - x * x / 2 - std::fabs(y) * 3 + 1 / (2 + z * z);
               });
  // integer powers of negative bases multiply out; a fractional power is exp(e log b)
  expectValues(model("my_model = x[1]^3 - (x[2]*x[2] + 1)^1.5;"),
               [](double x, double y, double) { return x * x * x - std::pow(y * y + 1, 1.5); });
}

TEST(HyperFun, SetOperatorsAreTheRFunctionsWithAlphaZero) {
  const std::string body =
      "array c[3];\n"
      "c = [0.5, 0, 0];\n"
      "s1 = hfSphere(x, c, 1.5);\n"
      "c = [-0.5, 0.3, 0];\n"
      "s2 = hfSphere(x, c, 1.2);\n"
      "c = [0, 0, 0.8];\n"
      "s3 = hfSphere(x, c, 1);\n";
  auto ball = [](double x, double y, double z, double cx, double cy, double cz, double r) {
    return r * r - sq(x - cx) - sq(y - cy) - sq(z - cz);
  };
  const auto s1 = [&](double x, double y, double z) { return ball(x, y, z, 0.5, 0, 0, 1.5); };
  const auto s2 = [&](double x, double y, double z) { return ball(x, y, z, -0.5, 0.3, 0, 1.2); };
  const auto s3 = [&](double x, double y, double z) { return ball(x, y, z, 0, 0, 0.8, 1); };
  // left to right, one level: s1 | s2 & s3 is (s1 | s2) & s3
  expectValues(model(body + "my_model = s1 | s2 & s3;"), [&](double x, double y, double z) {
    return meet(unite(s1(x, y, z), s2(x, y, z)), s3(x, y, z));
  });
  expectValues(model(body + "my_model = s1 \\ s2 \\ ~s3;"), [&](double x, double y, double z) {
    return meet(meet(s1(x, y, z), -s2(x, y, z)), s3(x, y, z));
  });
  // the tree keeps the operations as nodes: a difference of three, alpha 0
  const Model m = load(model(body + "my_model = s1 \\ s2 \\ s3;"));
  EXPECT_EQ(m.root->type->id, "difference");
  EXPECT_EQ(m.root->inputs.size(), 3u);
  EXPECT_EQ(m.root->real("alpha"), 0.0);
  EXPECT_EQ(m.root->inputs[0]->type->id, "formula");
  // arithmetic over solids is a formula with the solids as its inputs
  expectValues(model(body + "my_model = (s1 | s2) + 0.5 * s3 - 0.25;"),
               [&](double x, double y, double z) {
                 return unite(s1(x, y, z), s2(x, y, z)) + 0.5 * s3(x, y, z) - 0.25;
               });
}

TEST(HyperFun, PrimitivesHaveTheLibrarysValues) {
  const std::string c = "array c[3];\nc = [0.3, -0.2, 0.5];\n";
  const double cx = 0.3, cy = -0.2, cz = 0.5;
  expectValues(model(c + "my_model = hfEllipsoid(x, c, 1.5, 1, 0.7);"),
               [&](double x, double y, double z) {
                 return 1 - sq((x - cx) / 1.5) - sq((y - cy) / 1) - sq((z - cz) / 0.7);
               });
  expectValues(model(c + "my_model = hfCylinderY(x, c, 0.8);"),
               [&](double x, double, double z) { return 0.64 - sq(x - cx) - sq(z - cz); });
  expectValues(model(c + "my_model = hfEllCylZ(x, c, 0.8, 1.3);"), [&](double x, double y, double) {
    return 1 - sq((x - cx) / 0.8) - sq((y - cy) / 1.3);
  });
  expectValues(model(c + "my_model = hfConeX(x, c, 0.6);"), [&](double x, double y, double z) {
    return sq(x - cx) - sq((y - cy) / 0.6) - sq((z - cz) / 0.6);
  });
  expectValues(
      model(c + "my_model = hfTorusZ(x, c, 1.2, 0.4);"), [&](double x, double y, double z) {
        const double dx = x - cx, dy = y - cy, dz = z - cz;
        return 0.16 - dx * dx - dy * dy - dz * dz - 1.44 + 2 * 1.2 * std::sqrt(dx * dx + dy * dy);
      });
  expectValues(
      model(c + "my_model = hfTorusX(x, c, 1.2, 0.4);"), [&](double x, double y, double z) {
        const double dx = x - cx, dy = y - cy, dz = z - cz;
        return 0.16 - dx * dx - dy * dy - dz * dz - 1.44 + 2 * 1.2 * std::sqrt(dy * dy + dz * dz);
      });
  // the block: the slabs (x - v)(v + d - x) met two by two
  expectValues(model(c + "my_model = hfBlock(x, c, 2, 1, 1.5);"),
               [&](double x, double y, double z) {
                 const double a = (x - cx) * (cx + 2 - x), b = (y - cy) * (cy + 1 - y),
                              d = (z - cz) * (cz + 1.5 - z);
                 return meet(meet(a, b), d);
               });
  expectValues(model(c + "my_model = hfSuperell(x, c, 1.5, 1, 0.8, 0.5, 2.5);"),
               [&](double x, double y, double z) {
                 const double xt = std::fabs((x - cx) / 1.5), yt = std::fabs((y - cy) / 1),
                              zt = std::fabs((z - cz) / 0.8), s1 = 0.5, s2 = 2.5;
                 const double xy = std::pow(xt, 2 / s2) + std::pow(yt, 2 / s2);
                 return 1 - std::pow(xy, s2 / s1) - std::pow(zt, 2 / s1);
               });
}

TEST(HyperFun, SkeletalPrimitivesSumTheirKernels) {
  const std::string centres =
      "array x0[3], y0[3], z0[3], p[3], q[3];\n"
      "x0 = [0, 1, -0.5];\n y0 = [0, 0.5, -1];\n z0 = [0, -0.3, 0.6];\n"
      "p = [1.5, 2, 0.8];\n q = [1, 0.7, 1.3];\n";
  const double X0[3] = {0, 1, -0.5}, Y0[3] = {0, 0.5, -1}, Z0[3] = {0, -0.3, 0.6};
  const double P[3] = {1.5, 2, 0.8}, Q[3] = {1, 0.7, 1.3};
  auto r2 = [&](int i, double x, double y, double z) {
    return sq(x - X0[i]) + sq(y - Y0[i]) + sq(z - Z0[i]);
  };
  expectValues(model(centres + "my_model = hfBlobby(x, x0, y0, z0, p, q, 0.4);"),
               [&](double x, double y, double z) {
                 double s = 0;
                 for (int i = 0; i < 3; ++i) s += Q[i] * std::exp(-P[i] * r2(i, x, y, z));
                 return s - 0.4;
               });
  // Nishimura's pieces, as the manual gives them
  expectValues(model(centres + "my_model = hfMetaball(x, x0, y0, z0, q, p, 0.3);"),
               [&](double x, double y, double z) {
                 double s = 0;
                 for (int i = 0; i < 3; ++i) {
                   const double r = std::sqrt(r2(i, x, y, z)), d = P[i], b = Q[i];
                   if (r <= d / 3)
                     s += b * (1 - 3 * sq(r / d));
                   else if (r < d)
                     s += 1.5 * b * sq(1 - r / d);
                 }
                 return s - 0.3;
               });
  expectValues(model(centres + "my_model = hfSoft(x, x0, y0, z0, p, 0.2);"),
               [&](double x, double y, double z) {
                 double s = 0;
                 for (int i = 0; i < 3; ++i) {
                   const double rr = r2(i, x, y, z), d2 = P[i] * P[i];
                   if (std::sqrt(rr) <= P[i])
                     s += 1 - 22 * rr / (9 * d2) + 17 * rr * rr / (9 * d2 * d2) -
                          4 * rr * rr * rr / (9 * d2 * d2 * d2);
                 }
                 return s - 0.2;
               });
  expectValues(model("array v[6], w[2];\n v = [0, 0, 0, 1, 0.5, -0.5];\n w = [1.2, 0.9];\n"
                     "my_model = hfConvPoint(x, v, w, 0.3);"),
               [&](double x, double y, double z) {
                 const double v[6] = {0, 0, 0, 1, 0.5, -0.5}, s[2] = {1.2, 0.9};
                 double f = 0;
                 for (int i = 0; i < 2; ++i) {
                   const double rr = sq(v[3 * i] - x) + sq(v[3 * i + 1] - y) + sq(v[3 * i + 2] - z);
                   f += 1 / sq(1 + s[i] * s[i] * rr);
                 }
                 return f - 0.3;
               });
}

TEST(HyperFun, TransformationsMapTheArrayTheyAreGiven) {
  // inverse mappings of the point, applied in order to a copy of x; x itself is unchanged
  const std::string program = model(
      "array xt[3], c[3];\n"
      "xt[1] = x[1]; xt[2] = x[2]; xt[3] = x[3];\n"
      "c = [0, 0, 0];\n"
      "t = hfShift3D(xt, 1, -0.5, 0.25);\n"
      "t = hfRotate3DZ(xt, 0.7);\n"
      "t = hfScale3D(xt, 2, 1, 0.5);\n"
      "t = hfRotate3DY(xt, -0.4);\n"
      "t = hfRotate3DX(xt, 1.1);\n"
      "moved = hfEllipsoid(xt, c, 1, 0.6, 0.8);\n"
      "still = hfSphere(x, c, 0.5);\n"
      "my_model = moved | still;");
  expectValues(program, [](double x, double y, double z) {
    double p[3] = {x - 1, y + 0.5, z - 0.25};
    auto rotate = [](double& u, double& v, double t) {
      const double u2 = u * std::cos(t) + v * std::sin(t);
      const double v2 = -u * std::sin(t) + v * std::cos(t);
      u = u2;
      v = v2;
    };
    rotate(p[0], p[1], 0.7);
    p[0] /= 2;
    p[2] /= 0.5;
    rotate(p[2], p[0], -0.4);
    rotate(p[1], p[2], 1.1);
    const double moved = 1 - sq(p[0]) - sq(p[1] / 0.6) - sq(p[2] / 0.8);
    const double still = 0.25 - x * x - y * y - z * z;
    return unite(moved, still);
  });
  expectValues(model("array xt[3], c[3];\n xt[1] = x[1]; xt[2] = x[2]; xt[3] = x[3];\n"
                     "c = [0, 0, 0];\n"
                     "t = hfTwistZ(xt, -1, 1, 0, 1.5);\n"
                     "t = hfTaperX(xt, -1, 1, 0.5, 1.5);\n"
                     "t = hfStretch3D(xt, c, 1.5, 1, 0.75);\n"
                     "my_model = hfBlock(xt, c, 1, 0.5, 0.8);"),
               [](double x, double y, double z) {
                 double p[3] = {x, y, z};
                 const double t = (p[2] + 1) / 2, angle = t * 1.5;
                 const double px = p[0] * std::cos(angle) + p[1] * std::sin(angle);
                 const double py = -p[0] * std::sin(angle) + p[1] * std::cos(angle);
                 p[0] = px;
                 p[1] = py;
                 const double u = std::min(std::max((p[0] + 1) / 2, 0.0), 1.0);
                 const double scale = (1 - u) * 0.5 + u * 1.5;
                 p[1] /= scale;
                 p[2] /= scale;
                 p[0] /= 1.5;
                 p[2] /= 0.75;
                 const double a = p[0] * (1 - p[0]), b = p[1] * (0.5 - p[1]),
                              d = p[2] * (0.8 - p[2]);
                 return meet(meet(a, b), d);
               });
}

TEST(HyperFun, LoopsConditionsAndBodiesRunOverNumbers) {
  // a while loop places five balls; an if picks their radii; a body is called on a moved point
  const std::string program =
      "ball(x[3], a[1])\n{\n array c[3];\n c = [0, 0, 0];\n ball = hfSphere(x, c, 0.6);\n}\n"
      "my_model(x[3], a[1])\n{\n"
      " array c[3], xt[3];\n"
      " i = 0;\n"
      " u = -10;\n"
      " while i < 5 loop\n"
      "   c[1] = i - 2; c[2] = 0; c[3] = 0;\n"
      "   if i = 2 or i >= 4 then r = 0.5; else r = 0.3; endif;\n"
      "   u = u | hfSphere(x, c, r);\n"
      "   i = i + 1;\n"
      " endloop;\n"
      " xt[1] = x[1]; xt[2] = x[2] - 1; xt[3] = x[3];\n"
      " my_model = u | ball(xt, a);\n"
      "}\n";
  expectValues(program, [](double x, double y, double z) {
    double u = -10;
    for (int i = 0; i < 5; ++i) {
      const double r = (i == 2 || i >= 4) ? 0.5 : 0.3;
      u = unite(u, r * r - sq(x - (i - 2)) - y * y - z * z);
    }
    return unite(u, 0.36 - x * x - sq(y - 1) - z * z);
  });
  // the chain of unions is one union node of six inputs
  const Model m = load(program);
  ASSERT_EQ(m.root->type->id, "union");
  EXPECT_EQ(m.root->inputs.size(), 7u);  // -10, the five balls, the called ball
  // names for the features: the body's, a variable's, else the library call's
  EXPECT_EQ(m.labels.at(m.root.get()), "my_model");
  EXPECT_EQ(m.labels.at(m.root->inputs[1].get()), "hfSphere");
  EXPECT_EQ(m.labels.at(m.root->inputs[6].get()), "ball");
}

TEST(HyperFun, BlendsAreBlendNodesWithTheLibrarysValues) {
  const std::string body =
      "array c[3];\n c = [0, 0, 0];\n s = 1;\n"
      "b = hfBlock(x, c, 1, 1, 1);\n c = [0.5, 0.5, 1.2];\n"
      "t = hfSphere(x, c, 0.5);\n";
  auto block = [](double x, double y, double z) {
    return meet(meet(x * (1 - x), y * (1 - y)), z * (1 - z));
  };
  auto ball = [](double x, double y, double z) {
    return 0.25 - sq(x - 0.5) - sq(y - 0.5) - sq(z - 1.2);
  };
  expectValues(model(body + "my_model = hfBlendUni(b, t, 0.3, 0.5, 0.7);"),
               [&](double x, double y, double z) {
                 const double f1 = block(x, y, z), f2 = ball(x, y, z);
                 return unite(f1, f2) + 0.3 / (1 + sq(f1 / 0.5) + sq(f2 / 0.7));
               });
  expectValues(model(body + "my_model = hfBlendInt(b, t, -0.2, 0.5, 0.4);"),
               [&](double x, double y, double z) {
                 const double f1 = block(x, y, z), f2 = ball(x, y, z);
                 return meet(f1, f2) - 0.2 / (1 + sq(f1 / 0.5) + sq(f2 / 0.4));
               });
  const Model m = load(model(body + "my_model = hfBlendUni(b, t, 0.3, 0.5, 0.7);"));
  EXPECT_EQ(m.root->type->id, "blend_union");
  EXPECT_EQ(m.root->real("alpha"), 0.0);
  EXPECT_EQ(m.root->real("a2"), 0.7);
}

TEST(HyperFun, FunctionsComputeAsItsInterpreterDoes) {
  // mod of the values rounded to whole numbers, int towards zero, frac, logd, and sign, which
  // HyperFun's interpreter computes as 1 for every value
  expectValues(model("my_model = mod(3*x[1], 2.2) + int(2*x[2]) - frac(x[3]) + logd(5 + x[1]) "
                     "+ sign(x[2]) + max(x[1], x[2]) * min(x[3], 1) + atan2(x[2], x[1]);"),
               [](double x, double y, double z) {
                 const double m = std::fmod(std::floor(3 * x + 0.5), std::floor(2.2 + 0.5));
                 return m + std::trunc(2 * y) - (z - std::trunc(z)) + std::log10(5 + x) + 1 +
                        std::max(x, y) * std::min(z, 1.0) + std::atan2(y, x);
               });
}

TEST(HyperFun, ErrorsNameTheLineAndColumn) {
  EXPECT_EQ(errorOf("my_model(x[3], a[1])\n{\n  my_model = 1 +;\n}\n"),
            "test.hf:3:17: expected a value, found ';'");
  EXPECT_EQ(errorOf(model("my_model = hfSpere(x, x, 1);")),
            "test.hf:3:12: unknown function 'hfspere'");
  EXPECT_EQ(errorOf(model("if x[1] > 0 then r = 1; endif;\nmy_model = 1;")),
            "test.hf:3:4: this condition depends on the point (x); FRepCAD needs a number here");
  EXPECT_EQ(errorOf(model("r = 2 / (1 - 1);\nmy_model = r;")),
            "test.hf:3:7: division by zero (the divisor is 0)");
  EXPECT_EQ(errorOf(model("my_model = a[1] - x[1];")),
            "test.hf:3:12: a[1] is a parameter given to HyperFun from outside; FRepCAD is given "
            "none: write the value into the program");
  EXPECT_NE(errorOf(model("my_model = hfConvCurve(x, x, x, 1);")).find("convolution curves"),
            std::string::npos);
  EXPECT_NE(errorOf(model("my_model = x[1] @ x[2];")).find("Cartesian product"), std::string::npos);
  EXPECT_NE(errorOf(model("i = 0;\nwhile i < 1 loop\n j = 1;\nendloop;\nmy_model = 1;"))
                .find("more than 1000000 statements"),
            std::string::npos);
  EXPECT_NE(
      errorOf(model("array c[3];\nmy_model = hfSphere(x, c, 1);")).find("c[1] is used before"),
      std::string::npos);
  EXPECT_EQ(errorOf(model("array c[2];\nc = [1, 2, 3];\nmy_model = 1;")),
            "test.hf:4:1: c has 2 items; 3 numbers given");
  EXPECT_NE(errorOf("model(x[2], a[1])\n{\n model = x[1];\n}\n").find("FRepCAD's models are 3D"),
            std::string::npos);
  EXPECT_NE(errorOf(model("my_model = hfSphere(x, 1);")).find("hfsphere takes 3 arguments"),
            std::string::npos);
  // a long formula is fine (3,000 blobs: about 150,000 characters), one of over a million is
  // refused before it is built
  const std::string blobs =
      "array x0[3000], y0[3000], z0[3000], p[3000], q[3000];\n i = 1;\n"
      "while i <= 3000 loop\n x0[i] = 0.01 * i; y0[i] = 0; z0[i] = 0; p[i] = 3; q[i] = 1;\n"
      " i = i + 1;\nendloop;\n";
  EXPECT_EQ(errorOf(model(blobs + "my_model = hfBlobby(x, x0, y0, z0, p, q, 0.4);")), "(accepted)");
  std::string turns = "array p[3];\n p[1] = x[1]; p[2] = x[2]; p[3] = x[3];\n";
  for (int k = 0; k < 40; ++k) turns += "t = hfRotate3DZ(p, 0.1);\n";
  EXPECT_NE(errorOf(model(turns + "my_model = hfSphere(p, p, 1);")).find("longer than 1000000"),
            std::string::npos);
  // nesting a hostile file would use to overflow the stack is refused
  EXPECT_NE(
      errorOf(model("my_model = " + std::string(5000, '(') + "1" + std::string(5000, ')') + ";"))
          .find("nested deeper than"),
      std::string::npos);
}

// The programs in tests/data/hyperfun (which cli_test.sh also exports printable), each against
// HyperFun's definitions of what it calls, at 10,000 random points.
double slab(double p, double v, double d) {
  return (p - v) * (v + d - p);
}
double block(double x, double y, double z, const double v[3], const double d[3]) {
  return meet(meet(slab(x, v[0], d[0]), slab(y, v[1], d[1])), slab(z, v[2], d[2]));
}
void turn(double& u, double& v, double t) {  // HyperFun's inverse rotation of a pair
  const double u2 = u * std::cos(t) + v * std::sin(t), v2 = -u * std::sin(t) + v * std::cos(t);
  u = u2;
  v = v2;
}
double metaballKernel(double r, double b, double d) {
  if (r <= d / 3) return b * (1 - 3 * sq(r / d));
  return r < d ? 1.5 * b * sq(1 - r / d) : 0.0;
}
double softKernel(double r2, double d) {
  const double d2 = d * d;
  if (std::sqrt(r2) > d) return 0.0;
  return 1 - 22 * r2 / (9 * d2) + 17 * r2 * r2 / (9 * d2 * d2) -
         4 * r2 * r2 * r2 / (9 * d2 * d2 * d2);
}
double lineKernel(const double b[3], const double e[3], double s, double x, double y, double z) {
  const double l = std::sqrt(sq(e[0] - b[0]) + sq(e[1] - b[1]) + sq(e[2] - b[2]));
  const double ax = (e[0] - b[0]) / l, ay = (e[1] - b[1]) / l, az = (e[2] - b[2]) / l;
  const double dx = x - b[0], dy = y - b[1], dz = z - b[2];
  const double t = dx * ax + dy * ay + dz * az, d2 = dx * dx + dy * dy + dz * dz;
  const double p = std::sqrt(1 + s * s * (d2 - t * t));
  const double q = std::sqrt(1 + s * s * (d2 + l * l - 2 * l * t));
  return t / (2 * p * p * (p * p + s * s * t * t)) + (l - t) / (2 * p * p * q * q) +
         (std::atan(s * t / p) + std::atan(s * (l - t) / p)) / (2 * s * p * p * p);
}
double triangleKernel(double v[9], double s, double x, double y, double z) {
  double a1[3] = {v[0], v[1], v[2]}, a2[3] = {v[3], v[4], v[5]}, a3[3] = {v[6], v[7], v[8]};
  auto len = [](const double* p, const double* q) {
    return std::sqrt(sq(p[0] - q[0]) + sq(p[1] - q[1]) + sq(p[2] - q[2]));
  };
  const double l0 = len(a2, a1), l1 = len(a3, a2), l2 = len(a1, a3);
  double t1[3], t2[3], t3[3];
  if (l1 >= l2 && l1 > l0) {  // rotate so that a1-a2 is the longest side
    std::copy(a2, a2 + 3, t1), std::copy(a3, a3 + 3, t2), std::copy(a1, a1 + 3, t3);
  } else if (l2 >= l1 && l2 > l0) {
    std::copy(a3, a3 + 3, t1), std::copy(a1, a1 + 3, t2), std::copy(a2, a2 + 3, t3);
  } else {
    std::copy(a1, a1 + 3, t1), std::copy(a2, a2 + 3, t2), std::copy(a3, a3 + 3, t3);
  }
  double e21[3], e13[3];
  for (int k = 0; k < 3; ++k) e21[k] = t2[k] - t1[k], e13[k] = t1[k] - t3[k];
  const double L = len(t2, t1);
  const double t = -(e21[0] * e13[0] + e21[1] * e13[1] + e21[2] * e13[2]) / (L * L);
  double b[3], u[3], w[3];
  for (int k = 0; k < 3; ++k) b[k] = t1[k] + t * e21[k];
  const double ul = len(t2, b), vl = len(t3, b);
  for (int k = 0; k < 3; ++k) u[k] = (t2[k] - b[k]) / ul, w[k] = (t3[k] - b[k]) / vl;
  const double d[3] = {x - b[0], y - b[1], z - b[2]};
  const double d2 = sq(d[0]) + sq(d[1]) + sq(d[2]);
  const double uu = d[0] * u[0] + d[1] * u[1] + d[2] * u[2];
  const double vv = d[0] * w[0] + d[1] * w[1] + d[2] * w[2];
  const double h = len(t3, b), A1 = len(t1, b), A2 = len(t2, b);
  const double g = vv - h, m = A2 * g + uu * h, k = uu * h - A1 * g;
  const double C2 = 1 / (s * s) + d2 - uu * uu, C = std::sqrt(C2);
  const double q = C2 - vv * vv, ww = C2 - 2 * vv * h + h * h;
  const double A = std::sqrt(A1 * A1 * ww + h * h * (q + uu * uu) - 2 * A1 * h * uu * g);
  const double B = std::sqrt(A2 * A2 * ww + h * h * (q + uu * uu) + 2 * A2 * h * uu * g);
  const double n1 = A1 + uu, n2 = A2 - uu, n3 = A1 * n1 + vv * h, n4 = -A1 * uu - g * h,
               n5 = -A2 * n2 - vv * h, n6 = -A2 * uu + g * h;
  const double arc1 = k * (std::atan(n3 / A) + std::atan(n4 / A)) / A;
  const double arc2 = m * (std::atan(n5 / B) + std::atan(n6 / B)) / B;
  const double arc3 = vv * (std::atan(n1 / C) + std::atan(n2 / C)) / C;
  return (arc1 + arc2 + arc3) / (2 * q * s);
}

// HyperFun's arc kernel, as its library computes it (pi as 3.141592, 1e-6 added to the axis
// and the angle, an arc over 180 degrees as two pieces, the sign of p2 choosing atan or atanh).
double arcKernel(const double c[3], double r, double theta, const double axis[3], double angle,
                 double s, double x, double y, double z) {
  const double pi = 3.141592, rd = pi / 180, eps = 1e-6;
  angle += eps;
  double i = axis[0] + eps, j = axis[1] + eps, k = axis[2] + eps;
  double length = std::max(std::sqrt(i * i + j * j + k * k), eps);
  i /= length, j /= length, k /= length;
  auto turned = [](double i, double j, double k, double angle, const double p[3], double out[3]) {
    const double cs = std::cos(3.141592 / 180 * -angle), sn = std::sin(3.141592 / 180 * -angle),
                 o = 1 - cs;
    out[0] = (cs + i * i * o) * p[0] + (-k * sn + i * j * o) * p[1] + (j * sn + k * i * o) * p[2];
    out[1] = (k * sn + i * j * o) * p[0] + (cs + j * j * o) * p[1] + (-i * sn + j * k * o) * p[2];
    out[2] = (-j * sn + k * i * o) * p[0] + (i * sn + j * k * o) * p[1] + (cs + k * k * o) * p[2];
  };
  auto piece = [&](const double q[3], double th) {
    const double a = 2 * r * s * s, d2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
    const double b = 1 + r * r * s * s + s * s * d2;
    const double p2 = -std::pow(r * s, 4) +
                      2 * r * r * s * s * (s * s * (d2 - 2 * q[2] * q[2]) - 1) - sq(1 + s * s * d2);
    const double p1 = std::sqrt(std::fabs(p2)), p3 = p1 * p2;
    const double X = q[0], Y = q[1];
    const double f1 = b * Y / (X * p2 * (a * X - b)) +
                      (a * (X * X + Y * Y) * std::sin(th) - b * Y) /
                          (X * p2 * (a * (X * std::cos(th) + Y * std::sin(th)) - b));
    const double f2 = p2 < 0 ? 2 * b *
                                   (std::atan(-a * Y / p1) +
                                    std::atan((a * Y - (a * X + b) * std::tan(th / 2)) / p1)) /
                                   p3
                             : 2 * b *
                                   (std::atanh(a * Y / p1) +
                                    std::atanh(((a * X + b) * std::tan(th / 2) - a * Y) / p1)) /
                                   p3;
    return f1 + f2;
  };
  const double d[3] = {x - c[0], y - c[1], z - c[2]};
  double p[3];
  turned(i, j, k, angle, d, p);
  double f = 0;
  theta = std::min(theta, 360.0);
  if (theta > 180) {
    double q[3];
    turned(0, 0, 1, 180, p, q);
    f += piece(q, (theta - 180) * rd);
    theta = 180;
  }
  return f + piece(p, theta * rd);
}

struct ProgramCase {
  const char* file;
  Field expected;
};

const std::vector<ProgramCase>& programCases() {
  static const std::vector<ProgramCase> cases = {
      {"csg.hf",
       [](double x, double y, double z) {
         const double v[3] = {-1, -1, -1}, d[3] = {2, 2, 2};
         const double bores = unite(unite(0.45 * 0.45 - y * y - z * z, 0.16 - x * x - z * z),
                                    0.35 * 0.35 - x * x - y * y);
         return meet(meet(block(x, y, z, v, d), 1.35 * 1.35 - x * x - y * y - z * z), -bores);
       }},
      {"cones.hf",
       [](double x, double y, double z) {
         const double va[3] = {-1, -2, -2}, da[3] = {2, 4, 4}, vb[3] = {-2, -1.2, -2},
                      db[3] = {4, 2.4, 4}, vc[3] = {-2, -2, -0.8}, dc[3] = {4, 4, 1.6};
         const double cx = meet(x * x - sq(y / 0.5) - sq(z / 0.5), block(x, y, z, va, da));
         const double cy = meet(y * y - sq(x / 0.4) - sq(z / 0.4), block(x, y, z, vb, db));
         const double cz = meet(z * z - sq(x / 0.6) - sq(y / 0.6), block(x, y, z, vc, dc));
         return unite(unite(cx, cy), cz);
       }},
      {"tori.hf",
       [](double x, double y, double z) {
         const double r2 = x * x + y * y + z * z;
         const double tz = 0.09 - r2 - 1.44 + 2 * 1.2 * std::sqrt(x * x + y * y);
         const double p2 = sq(x - 1.2) + y * y + z * z;
         const double tx = 0.0625 - p2 - 1 + 2 * 1 * std::sqrt(y * y + z * z);
         const double q2 = sq(x + 1.2) + y * y + z * z;
         const double ty = 0.04 - q2 - 0.81 + 2 * 0.9 * std::sqrt(sq(x + 1.2) + z * z);
         return unite(unite(tz, tx), ty);
       }},
      {"quadrics.hf",
       [](double x, double y, double z) {
         const double v[3] = {-1.5, -1.5, -1.5}, d[3] = {3, 3, 3};
         const double e = 1 - sq(x / 1.4) - sq(y / 0.9) - sq(z / 0.7);
         const double rods =
             meet(unite(unite(1 - sq(y / 0.3) - sq(z / 0.5), 1 - sq(x / 0.45) - sq(z / 0.25)),
                        1 - sq(x / 0.2) - sq(y / 0.35)),
                  block(x, y, z, v, d));
         const double s1 = 0.4, s2 = 1.6;
         const double xy =
             std::pow(std::fabs(x / 0.8), 2 / s2) + std::pow(std::fabs(y / 0.6), 2 / s2);
         const double cap =
             1 - std::pow(xy, s2 / s1) - std::pow(std::fabs((z - 1.2) / 0.4), 2 / s1);
         return unite(unite(e, rods), cap);
       }},
      {"blobs.hf",
       [](double x, double y, double z) {
         double f = 0;
         for (int i = 1; i <= 6; ++i) {
           const double t = (i - 1) * 3.14159265358979 / 3;
           const double r2 = sq(x - std::cos(t)) + sq(y - std::sin(t)) + sq(z - 0.2 * (i - 3.5));
           f += (1 + 0.1 * i) * std::exp(-3 * r2);
         }
         return f - 0.4;
       }},
      {"metaballs.hf",
       [](double x, double y, double z) {
         const double cx[3] = {-1, 0, 1}, cy[3] = {0, 0.4, 0}, cz[3] = {0, 0, 0.3},
                      b[3] = {1, 1.2, 0.8}, d[3] = {1.6, 1.4, 1.5};
         double meta = 0;
         for (int i = 0; i < 3; ++i)
           meta +=
               metaballKernel(std::sqrt(sq(x - cx[i]) + sq(y - cy[i]) + sq(z - cz[i])), b[i], d[i]);
         const double soft = softKernel(x * x + sq(y + 1) + z * z, 1.2) +
                             softKernel(x * x + sq(y + 1.6) + sq(z - 0.4), 1) - 0.25;
         return unite(meta - 0.3, soft);
       }},
      {"convolution.hf",
       [](double x, double y, double z) {
         const double point = 1 / sq(1 + 4 * (x * x + y * y + sq(z - 1.2))) - 0.2;
         const double b1[3] = {-1, 0, 0}, e1[3] = {1, 0, 0}, b2[3] = {0, -1, 0},
                      e2[3] = {0, 1, 0.5};
         const double lines =
             lineKernel(b1, e1, 2.5, x, y, z) + lineKernel(b2, e2, 2, x, y, z) - 0.5;
         double tri[9] = {-0.8, -0.6, -0.8, 0.9, -0.5, -0.7, 0.1, 0.8, -0.9};
         return point + lines + triangleKernel(tri, 3, x, y, z) - 0.3;
       }},
      {"blends.hf",
       [](double x, double y, double z) {
         const double vp[3] = {-1.5, -1.5, -0.3}, dp[3] = {3, 3, 0.5}, vc[3] = {-2, -2, -0.1},
                      dc[3] = {4, 4, 1.8};
         const double plate = block(x, y, z, vp, dp);
         const double post = meet(0.25 - x * x - y * y, block(x, y, z, vc, dc));
         const double ball = 0.81 - x * x - y * y - sq(z - 1.6);
         const double top = meet(post, ball) + 0.1 / (1 + sq(post / 0.3) + sq(ball / 0.3));
         return unite(plate, top) + 0.15 / (1 + sq(plate / 0.4) + sq(top / 0.4));
       }},
      {"transforms.hf",
       [](double x, double y, double z) {
         double p[3] = {x - 0.4, y, z - 0.2};
         turn(p[0], p[1], 0.6);
         turn(p[1], p[2], 0.3);
         p[0] /= 1.5;
         p[2] /= 0.8;
         const double v[3] = {-0.5, -0.3, -0.2}, d[3] = {1, 0.6, 0.4};
         const double slabs = block(p[0], p[1], p[2], v, d);
         double q[3] = {0.2 + (x - 0.2) / 1.8, y / 0.7, z};
         turn(q[2], q[0], -0.5);
         const double ell = 1 - sq(q[0] / 0.6) - sq(q[1] / 0.5) - sq(q[2] / 0.4);
         return unite(slabs, ell);
       }},
      {"deformations.hf",
       [](double x, double y, double z) {
         double u = -10;
         for (int axis = 0; axis < 3; ++axis)
           for (int kind = 0; kind < 2; ++kind) {
             double p[3] = {x, y, z};
             if (kind == 0) {
               const double lo = -1, hi = 1;
               const double th[3][2] = {{0, 1.2}, {0.3, -0.9}, {-0.5, 0.5}};
               const double t = (p[axis] - lo) / (hi - lo);
               const double angle = (1 - t) * th[axis][0] + t * th[axis][1];
               const int pair[3][2] = {{1, 2}, {2, 0}, {0, 1}};
               turn(p[pair[axis][0]], p[pair[axis][1]], angle);
             } else {
               const double ends[3][2] = {{-1, 1}, {-0.8, 0.8}, {-1, 0.5}};
               const double scales[3][2] = {{0.6, 1.3}, {1.4, 0.5}, {0.7, 1}};
               const double t = std::min(
                   std::max((p[axis] - ends[axis][0]) / (ends[axis][1] - ends[axis][0]), 0.0), 1.0);
               const double scale = (1 - t) * scales[axis][0] + t * scales[axis][1];
               for (int k = 0; k < 3; ++k)
                 if (k != axis) p[k] /= scale;
             }
             double c[3] = {-1.1, -0.25, -0.15};
             c[axis] = -1;
             const double sizes[3][3] = {{2, 0.5, 0.3}, {0.5, 2, 0.3}, {0.5, 0.3, 2}};
             u = unite(u, block(p[0], p[1], p[2], c, sizes[axis]));
           }
         return u;
       }},
      {"arcs.hf",
       [](double x, double y, double z) {
         const double c1[3] = {0, 0, 0}, c2[3] = {0.3, 0.2, 0.4}, a1[3] = {1, 0, 0},
                      a2[3] = {0, 1, 0};
         const double f = arcKernel(c1, 1, 180, a1, 30, 3, x, y, z) +
                          arcKernel(c2, 0.7, 270, a2, 60, 2.5, x, y, z) - 0.25;
         return meet(f, 4 - x * x - y * y - z * z);
       }},
      {"noise.hf",
       [](double x, double y, double z) {
         const double sx = std::sin(4 * x), sy = std::sin(4 * y), sz = std::sin(4 * z);
         const double k = 1 / 1.17;
         const double serx = sx + k * std::sin(4 * x / 1.35 + 0.5 * sz);
         const double sery = sy + k * std::sin(4 * y / 1.35 + 0.5 * sx);
         const double serz = sz + k * std::sin(4 * z / 1.35 + 0.5 * sy);
         return 1 - x * x - y * y - z * z + 0.15 * serx * sery * serz;
       }},
      {"bodies.hf",
       [](double x, double y, double z) {
         auto ring = [](double px, double py, double pz) {
           return 0.0625 - px * px - py * py - pz * pz - 0.64 + 1.6 * std::sqrt(px * px + py * py);
         };
         double p[3] = {x + 0.6, y, z};
         turn(p[1], p[2], 1.5707963267949);
         const double pair = unite(ring(x - 0.6, y, z), ring(p[0], p[1], p[2]));
         // mod(17, 5) + int(2.7) - frac(0.5) + sign(-3) + logd(100) = 6.5 > 6: r = 0.3
         const double ball = 0.09 - x * x - y * y - sq(z - 1);
         return unite(pair, ball) + 0.01 * std::sin(4 * x) * std::cos(3 * y);
       }},
  };
  return cases;
}

std::string programText(const std::string& file) {
  std::ifstream in(std::string(FREP_SOURCE_DIR) + "/tests/data/hyperfun/" + file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(HyperFun, EveryLibraryCallAgreesWithHyperFunAtTenThousandPoints) {
  for (const ProgramCase& c : programCases()) {
    const std::string text = programText(c.file);
    ASSERT_FALSE(text.empty()) << c.file;
    const Program p = compile(importHyperFun(text, c.file).root);
    std::mt19937 g(17);
    std::uniform_real_distribution<double> u(-2.2, 2.2);
    double worst = 0;
    for (int i = 0; i < 10000; ++i) {
      const double x = u(g), y = u(g), z = u(g);
      const double want = c.expected(x, y, z);
      worst = std::max(worst, std::fabs(p.eval(x, y, z) - want) / (1.0 + std::fabs(want)));
    }
    EXPECT_LT(worst, 1e-9) << c.file;
  }
}

}  // namespace
}  // namespace frep
