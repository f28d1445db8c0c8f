"""The frepcore Python module on its own: the pythonic API, errors, progress and cancel,
checked export."""

import inspect
import math
import os
import pathlib

import pytest

import frepcore as fc

SOURCE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")


def csg():
    part = fc.box((2, 2, 2), corner=(-1, -1, -1)) & fc.sphere(1.3)
    for axis in ((1, 0, 0), (0, 1, 0), (0, 0, 1)):
        part = part - fc.cylinder(0.5, 0, axis=axis)
    return part


def test_operators_build_flat_trees():
    a, b, c = fc.sphere(1), fc.box((1, 1, 1)), fc.torus(2, 0.3)
    u = a | b | c
    assert u.type == "union" and len(u.inputs) == 3
    assert (a & b).type == "intersection"
    d = a - b - c
    assert d.type == "difference" and len(d.inputs) == 3
    assert (~a)(0, 0, 0) == -a(0, 0, 0)
    assert u(2, 0, 0) == pytest.approx(0.3)  # on the torus' tube centre circle


def test_positional_parameters_follow_the_documented_order():
    cyl = fc.cylinder(0.4, 3)
    assert cyl.params["radius"] == 0.4 and cyl.params["length"] == 3
    s = fc.sphere(2, (1, 0, 0))
    assert s(1, 0, 0) == pytest.approx(2)
    moved = fc.sphere(1).translate((5, 0, 0))
    assert moved(5, 0, 0) == pytest.approx(1)
    with pytest.raises(TypeError, match="at most 2 parameters"):
        fc.sphere(1, (0, 0, 0), 3)


def test_errors_name_the_parameter_and_what_is_allowed():
    with pytest.raises(ValueError, match=r"parameter 'radius' -1 is out of range; allowed: \(0, inf\)"):
        fc.sphere(-1)
    with pytest.raises(ValueError, match="unknown parameter 'radus'"):
        fc.sphere(radus=1)
    with pytest.raises(ValueError, match="needs 3"):
        fc.box((1, 1))
    assert fc.check_param("sphere", "radius", 2.0) == ""
    assert "out of range" in fc.check_param("sphere", "radius", 0.0)


def test_gradient_and_values_agree_with_point_evaluation():
    part = csg()
    pts = [(0.1 * i, 0.07 * i, -0.05 * i) for i in range(-10, 11)]
    assert part.values(pts) == [part(*p) for p in pts]
    f, g = part.gradient(0.9, 0.6, 0.7)
    assert f == part(0.9, 0.6, 0.7) and math.isclose(sum(x * x for x in g), 1.0, rel_tol=1e-9)


def test_bounds_and_mesh_volume():
    b = fc.sphere(1, (2, 0, 0)).bounds()
    assert b["bounded"] and b["box"][0][0] == pytest.approx(1, abs=1e-3)
    m = fc.sphere(1).mesh(cells=64)
    assert m.volume() == pytest.approx(4 / 3 * math.pi, rel=0.01)
    with pytest.raises(ValueError, match="unbounded"):
        fc.halfspace().mesh()
    with pytest.raises(ValueError, match="empty"):
        (fc.sphere(1) & fc.sphere(1, (3, 0, 0))).mesh()


def test_a_mesh_says_where_parts_thinner_than_a_cell_were_passed_over(tmp_path):
    # a fin 0.3 cell thick between two layers of grid points (x = -0.05 and 0.05)
    fin = fc.sphere(0.5) | fc.box((0.03, 0.3, 0.3), corner=(-0.015, 0.6, 0.6))
    box = ((-1, -1, -1), (1, 1, 1))
    thin = fin.mesh(0.1, bbox=box).thin_parts
    assert (thin["solid"], thin["gaps"], thin["tips"]) == (9, 0, 0)
    assert thin["example"][1:] == pytest.approx((0.65, 0.65))
    assert abs(thin["example"][0]) <= 0.015
    assert fc.sphere(0.5).mesh(0.1, bbox=box).thin_parts["solid"] == 0
    report = fin.export(str(tmp_path / "fin.stl"), 0.1, bbox=box)
    assert report["thin_parts"]["solid"] == 9
    assert thin["refined_cubes"] == 0


def test_refine_thin_parts_meshes_the_fin_the_grid_missed(tmp_path):
    fin = fc.sphere(0.5) | fc.box((0.03, 0.3, 0.3), corner=(-0.015, 0.6, 0.6))
    box = ((-1, -1, -1), (1, 1, 1))
    plain = fin.mesh(0.1, bbox=box)
    refined = fin.mesh(0.1, bbox=box, refine="thin-parts")
    assert refined.thin_parts["refined_cubes"] > 0
    # the fin (0.03 x 0.3 x 0.3 = 0.0027) is there now, as a second piece
    assert refined.volume() - plain.volume() == pytest.approx(0.0027, rel=0.2)
    report = fin.export(str(tmp_path / "fin.stl"), 0.1, bbox=box, refine="thin-parts")
    assert report["printable"] and report["components"] == 2
    assert report["thin_parts"]["refined_cubes"] == refined.thin_parts["refined_cubes"]


def test_refine_levels_mesh_a_fin_between_the_half_cell_points(tmp_path):
    # 0.03 thick, round a point of the quarter-cell grid: one level of refinement misses it
    fin = fc.sphere(0.5) | fc.box((0.03, 0.3, 0.3), corner=(0.01, 0.6, 0.6))
    box = ((-1, -1, -1), (1, 1, 1))
    plain = fin.mesh(0.1, bbox=box)
    one = fin.mesh(0.1, bbox=box, refine="thin-parts")
    two = fin.mesh(0.1, bbox=box, refine="thin-parts", refine_levels=2)
    assert one.volume() == pytest.approx(plain.volume(), abs=1e-4)
    assert "refined_levels" not in one.thin_parts
    assert two.thin_parts["refined_levels"] == 2
    assert two.thin_parts["refined_deeper_cubes"] > 0
    assert two.volume() - plain.volume() == pytest.approx(0.0027, rel=0.2)
    report = fin.export(str(tmp_path / "fin.stl"), 0.1, bbox=box, refine="thin-parts",
                        refine_levels=2)
    assert report["printable"] and report["components"] == 2
    with pytest.raises(ValueError, match="refine_levels must be a whole number from 1 to 3, got 4"):
        fin.mesh(0.1, bbox=box, refine="thin-parts", refine_levels=4)


def test_straighten_creases_merges_onto_the_twists_creases(tmp_path):
    twist, _ = fc.load(os.path.join(SOURCE, "examples", "twist.json"))
    plain = twist.mesh(cells=48)
    straight = twist.mesh(cells=48, straighten_creases=True)
    assert straight.triangle_count < plain.triangle_count
    assert straight.straightened["merged"] > 0 and not hasattr(plain, "straightened")
    assert straight.volume() == pytest.approx(2.0, rel=0.005)
    assert straight.check()["printable"]
    # before a simplification: fewer triangles still
    simple = twist.mesh(cells=48, straighten_creases=True, tolerance=0.005)
    assert simple.triangle_count < straight.triangle_count / 4
    report = twist.export(str(tmp_path / "t.stl"), cells=48, straighten_creases=True)
    assert report["printable"] and report["triangles"] == straight.triangle_count
    assert report["straightened"]["merged"] > 0 and report["straightened"]["seconds"] > 0
    assert "straightened" not in twist.export(str(tmp_path / "p.stl"), cells=48)
    with pytest.raises(ValueError, match="straighten_creases needs sharp_features"):
        twist.mesh(cells=48, straighten_creases=True, sharp_features=False)


def test_a_preview_too_large_for_the_memory_is_refused_with_the_figures():
    # a unit sphere at 1e-4: about 6e10 triangles, refused before any allocation
    with pytest.raises(ValueError, match=r"million triangles.*GB.*use a cell size of at least"):
        fc.sphere(1).mesh(resolution=1e-4)


def test_export_checks_and_writes(tmp_path):
    out = str(tmp_path / "part.stl")
    seen = []
    report = csg().export(out, cells=48, progress=lambda f: seen.append(f))
    assert report["printable"] and os.path.getsize(out) == 84 + 50 * report["triangles"]
    assert seen == sorted(seen) and seen[-1] == 1.0
    assert fc.read_mesh(out).triangle_count == report["triangles"]


def test_export_with_a_tolerance_simplifies_and_still_checks(tmp_path):
    full = csg().export(str(tmp_path / "full.stl"), cells=48)
    out = str(tmp_path / "part.stl")
    seen = []
    report = csg().export(out, cells=48, tolerance=0.01, progress=lambda f: seen.append(f))
    assert report["printable"] and report["written"]
    assert report["triangles_before_simplify"] == full["triangles"]
    assert 5 * report["triangles"] < full["triangles"]
    # (a face the grid had cut off by more than the tolerance is only ever made better)
    assert report["largest_distance"] > 0
    assert seen == sorted(seen) and seen[-1] == 1.0
    with pytest.raises(ValueError, match="tolerance must be a distance > 0"):
        csg().export(str(tmp_path / "bad.stl"), cells=48, tolerance=-1)
    assert not os.path.exists(str(tmp_path / "bad.stl"))


def test_cancel_raises_and_writes_nothing(tmp_path):
    out = str(tmp_path / "part.stl")
    with pytest.raises(fc.Cancelled):
        csg().export(out, cells=400, progress=lambda f: f < 0.1)
    assert os.listdir(str(tmp_path)) == []


def test_exception_in_progress_callback_propagates():
    def boom(fraction):
        raise KeyError("from callback")

    with pytest.raises(KeyError, match="from callback"):
        fc.sphere(1).mesh(cells=300, progress=boom)


def test_json_round_trip_is_exact():
    part = csg()
    again = fc.Shape(fc.parse_model(part.to_json())["root"])
    pts = [(0.3 * i, -0.2 * i, 0.1 * i) for i in range(-5, 6)]
    assert again.values(pts) == part.values(pts)


def test_functions_exist_for_every_registry_type():
    for info in fc.node_types():
        fn = getattr(fc, info["type"])
        assert info["doc"] in fn.__doc__


def test_modelling_set_reads_naturally_in_scripts():
    """Deformations and field operations as methods, microstructures as functions, with the
    parameter most scripts set first."""
    bar = fc.box((1, 1, 2), (-0.5, -0.5, -1))
    twisted = bar.twist(90)
    assert twisted.node.params["rate"] == 90
    tapered = bar.taper(0.5, 2)
    assert (tapered.node.params["scale2"], tapered.node.params["length"]) == (0.5, 2)
    hollow = fc.sphere(1).shell(0.1)
    assert hollow(0.95, 0, 0) > 0 > hollow(0.5, 0, 0)
    assert fc.sphere(1).offset(0.5)(1.4, 0, 0) > 0
    lattice = fc.gyroid(0.5, 0.2) & fc.sphere(1)
    assert lattice(0, 0, 0) == pytest.approx(0.2)
    morph = fc.metamorphosis(fc.sphere(1), bar, t=0.25)
    assert morph(0, 0, 0) == pytest.approx(0.75 * 1 + 0.25 * 0.5)


def test_gallery_shows_every_registry_type():
    """docs/gallery.md (make screenshots) has a section and a GUI picture per node type."""
    docs = os.path.join(os.environ["FREP_SOURCE_DIR"], "docs")
    with open(os.path.join(docs, "gallery.md"), encoding="utf-8") as f:
        text = f.read()
    for t in fc.node_types():
        assert "### %s\n" % t["type"] in text, \
            "%s missing from docs/gallery.md: run make screenshots" % t["type"]
        assert os.path.exists(os.path.join(docs, "images", "nodes", t["type"] + ".png"))


# -- meshes and OpenVDB grids as solids ----------------------------------------------------

def test_meshes_become_exact_solids_and_open_ones_are_refused(tmp_path):
    path = str(tmp_path / "ball.stl")
    fc.sphere(1.0).mesh(cells=48).write(path)
    from_file = fc.from_mesh(path)
    assert from_file.type == "mesh_sdf"
    assert from_file(0, 0, 0) == pytest.approx(1.0, abs=0.02)
    assert from_file(2, 0, 0) == pytest.approx(-1.0, abs=0.02)
    # A model file holds it (the path made absolute), and it loads back from anywhere.
    model = tmp_path / "m.json"
    model.write_text(from_file.to_json())
    again, _ = fc.load(str(model))
    assert again(0.5, 0, 0) == from_file(0.5, 0, 0)
    # In memory: a Mesh, or points and triangles.
    mesh = fc.read_mesh(path)
    exact = fc.from_mesh(mesh)
    assert exact(0.3, 0.2, 0.1) == from_file(0.3, 0.2, 0.1)
    grid = fc.from_mesh((mesh.points, mesh.triangles), method="grid", voxel=0.02)
    assert grid(0, 0, 0.95) == pytest.approx(from_file(0, 0, 0.95), abs=0.02)
    with pytest.raises(OSError, match="3 border edges"):
        fc.from_mesh(([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [(0, 1, 2)]))
    with pytest.raises(ValueError, match="refers to no point"):
        fc.Mesh([(0, 0, 0)], [(0, 1, 2)])
    with pytest.raises(OSError, match="missing.stl"):
        fc.from_mesh(str(tmp_path / "missing.stl"))(0, 0, 0)


def test_level_sets_round_trip_through_vdb_files(tmp_path):
    part = fc.sphere(1.0) - fc.box((1, 1, 1))
    path = str(tmp_path / "part.vdb")
    info = part.to_vdb(path, cells=48)
    assert info["grid_class"] == "level set" and info["value_type"] == "float"
    assert info["active_voxels"] > 1000
    listed = fc.vdb_grids(path)
    assert [g["name"] for g in listed] == ["surface"]
    assert "file_voxel_count" in listed[0]["metadata"]
    back = fc.from_vdb(path)
    # Distances within the narrow band (3 voxels), the sign beyond it.
    for p in ((0, 0, -0.95), (-0.9, 0, 0), (0, -1.02, 0)):
        assert back(*p) == pytest.approx(part(*p), abs=0.02)
    for p in ((-0.5, -0.5, -0.5), (0.5, 0.5, 0.5), (1.5, 0, 0), (0.2, -0.3, 0.1)):
        assert (back(*p) > 0) == (part(*p) > 0), p
    quadratic = fc.from_vdb(path, interpolation="quadratic")
    assert quadratic(0, 0, -0.9) == pytest.approx(back(0, 0, -0.9), abs=0.02)
    report = back.export(str(tmp_path / "part.stl"), cells=48)
    assert report["printable"], report["text"]
    mesh = fc.vdb_to_mesh(path)
    assert mesh.check()["printable"]
    assert mesh.volume() == pytest.approx(report["volume"], rel=0.05)
    with pytest.raises(ValueError, match="no grid named 'density'"):
        fc.from_vdb(path, grid="density")(0, 0, 0)
    # A fog volume: 0 outside, 1 inside; as a solid above iso 0.5 it is the same part.
    fog = str(tmp_path / "fog.vdb")
    assert part.to_vdb(fog, cells=48, fog=True)["grid_class"] == "fog volume"
    density = fc.from_vdb(fog, iso=0.5)
    for p in ((-0.5, -0.5, -0.5), (0.5, 0.5, 0.5), (1.5, 0, 0), (0, 0, -0.9)):
        assert (density(*p) > 0) == (part(*p) > 0), p
    (tmp_path / "bad.vdb").write_bytes(b"not a volume")
    with pytest.raises(OSError, match="bad.vdb"):
        fc.vdb_grids(str(tmp_path / "bad.vdb"))


def test_a_vdb_that_crashes_openvdb_s_reader_is_an_os_error_not_a_crash():
    # Its damaged compressed leaf overruns OpenVDB's buffer: read in this process it aborts
    # the interpreter (malloc(): invalid size); frepcad reads it first and says so.
    damaged = os.path.join(os.path.dirname(__file__), "..", "data", "damaged_leaf.vdb")
    assert fc.vdb_reader() and os.access(fc.vdb_reader(), os.X_OK)
    for read in (fc.vdb_grids, fc.vdb_to_mesh, lambda p: fc.from_vdb(p)(0, 0, 0)):
        with pytest.raises(OSError, match="damaged_leaf.vdb: the OpenVDB file is damaged"):
            read(damaged)


def bending_lattice():
    """A 3 x 1 x 1 lattice around a bar whose two middle planes of points are lifted."""
    lattice = fc.Lattice((-1.3, -0.4, -0.4), (1.3, 0.4, 0.4), (3, 1, 1))
    for i in (1, 2):
        for j in (0, 1):
            for k in (0, 1):
                p = lattice.points[(i * 2 + j) * 2 + k]
                lattice.set_point(i, j, k, (p[0], p[1], p[2] + 0.9))
    return lattice


def test_lattices_bend_solids_meshes_and_volumes_alike(tmp_path):
    lattice = bending_lattice()
    assert lattice.find_fold() is None
    assert lattice.divisions == [3, 1, 1] and len(lattice.points) == 16
    # the inverse undoes the map
    moved = lattice.deform((0.3, 0.1, 0.05))
    assert moved[2] > 0.3
    assert max(abs(a - b) for a, b in zip(lattice.inverse(moved), (0.3, 0.1, 0.05))) < 1e-9
    # a lattice file round-trips
    path = str(tmp_path / "bend.json")
    lattice.write(path)
    assert fc.read_lattice(path).points == lattice.points
    # the bar as a function and as a mesh, bent alike: both printable, the same volume
    bar = fc.box((2.4, 0.5, 0.5), corner=(-1.2, -0.25, -0.25))
    pulled = bar.deform(lattice).mesh(cells=80)
    pushed = fc.deform_mesh(bar.mesh(cells=80), lattice)
    assert pulled.check()["printable"] and pushed.check()["printable"]
    assert abs(pulled.volume() - pushed.volume()) < 0.03 * pushed.volume()
    # the same bar as a level set: deformed without gaps, every grid written
    vdb = str(tmp_path / "bar.vdb")
    bar.to_vdb(vdb, cells=48)
    out = str(tmp_path / "bent.vdb")
    grids = fc.deform_vdb(vdb, out, lattice)
    assert grids[0]["grid_class"] == "level set"
    assert fc.vdb_to_mesh(out).check()["printable"]
    with pytest.raises(Exception, match="interpolation 'cubic' is not allowed"):
        fc.deform_vdb(vdb, out, lattice, interpolation="cubic")
    with pytest.raises(Exception, match="lattice has 16"):
        fc.Lattice((-1, -1, -1), (1, 1, 1), (3, 1, 1), points=[(0, 0, 0)])


def test_several_objects_go_into_one_checked_3mf(tmp_path):
    ball = fc.sphere(1).mesh(bbox=((-1.2, -1.2, -1.2), (1.2, 1.2, 1.2)), resolution=0.1)
    block = fc.translate(fc.box(size=(1, 1, 1)), offset=(3, 0, 0))
    block = block.mesh(bbox=((2.8, -0.2, -0.2), (4.2, 1.2, 1.2)), resolution=0.1)
    path = str(tmp_path / "two.3mf")
    report = fc.write_3mf([("ball", ball), ("block", block)], path, unit="cm",
                          metadata={"Title": "two"})
    assert report["printable"] and report["written"]
    assert [o["name"] for o in report["objects"]] == ["ball", "block"]
    back = fc.read_3mf(path)
    assert [n for n, _ in back["objects"]] == ["ball", "block"]
    assert back["unit"] == "cm" and back["metadata"]["Title"] == "two"
    assert back["objects"][0][1].triangle_count == ball.triangle_count
    # an inside-out object: checked, refused by name, nothing written
    flipped = fc.Mesh(ball.points, [(a, c, b) for a, b, c in ball.triangles])
    refused = str(tmp_path / "refused.3mf")
    report = fc.write_3mf([("ball", ball), ("flipped", flipped)], refused)
    assert not report["printable"] and not report["written"]
    assert not os.path.exists(refused)
    assert "not outward" in report["objects"][1]["reasons"][0]


def test_repair_printability_and_deviation_of_a_mesh():
    ball = fc.sphere(1).mesh(bbox=((-1.2, -1.2, -1.2), (1.2, 1.2, 1.2)), resolution=0.1)
    holed = fc.Mesh(ball.points, ball.triangles[:-3])
    fixed, report = holed.repair()
    assert not report["printable_before"] and report["printable"], report["text"]
    assert any("filled" in a for a in report["actions"])
    assert fixed.check()["printable"]
    assert fixed.deviation(ball)["hausdorff"] < 0.05
    p = fixed.printability(min_wall=0.5, density=fc.materials()["pla"])
    assert p["print"]["min_wall"] > 1.8  # a ball of diameter 2
    assert p["print"]["thin_triangles"] == 0
    assert len(p["thickness"]) == fixed.triangle_count
    assert abs(p["print"]["mass_g"] - 1.24 * fixed.volume() / 1000) < 1e-6
    with pytest.raises(ValueError, match="rebuild policy"):
        holed.repair(rebuild="sometimes")
    assert report["accepted"] and report["departures"] == []
    # an open bowl: its cap would be invented surface, so the repair is printable but not
    # accepted, with the figure, until the bound covers the cap
    bowl = fc.Mesh(ball.points, [t for t in ball.triangles
                                 if sum(ball.points[v][2] for v in t) < 0])
    _, refused = bowl.repair()
    assert not refused["accepted"], refused["text"]
    assert "surface invented" in refused["departures"][0]
    assert refused["result_to_input"] > 0.5 > refused["deviation_bound"]
    _, capped = bowl.repair(max_deviation=1.5)
    assert capped["accepted"] and capped["deviation_bound"] == 1.5


def test_the_cube_mesher_makes_a_third_of_the_tetrahedra_triangles():
    part = csg()
    box = ((-1.2, -1.2, -1.2), (1.2, 1.2, 1.2))
    cubes = part.mesh(0.05, bbox=box)
    tetra = part.mesh(0.05, bbox=box, mesher="tetra")
    chamfered = part.mesh(0.05, bbox=box, sharp_features=False)
    assert 2.5 * cubes.triangle_count < tetra.triangle_count
    assert chamfered.triangle_count < cubes.triangle_count  # creases cost a fan each
    for m in (cubes, tetra, chamfered):
        assert m.check()["printable"]
    with pytest.raises(ValueError, match="mesher must be cubes or tetra, got 'dual'"):
        part.mesh(0.05, bbox=box, mesher="dual")


def test_flat_vertices_go_by_default_and_the_mesh_stays_printable(tmp_path):
    part = csg()
    box = ((-1.2, -1.2, -1.2), (1.2, 1.2, 1.2))
    full = part.mesh(0.05, bbox=box, drop_flat_vertices=False)
    fewer = part.mesh(0.05, bbox=box)
    assert fewer.triangle_count < 0.95 * full.triangle_count
    # two triangles go with each vertex
    assert (full.triangle_count - fewer.triangle_count
            == 2 * (full.vertex_count - fewer.vertex_count))
    assert fewer.check()["printable"]
    report = part.export(str(tmp_path / "fewer.stl"), bbox=box, resolution=0.05)
    assert report["written"] and report["triangles"] == fewer.triangle_count
    report = part.export(str(tmp_path / "full.stl"), bbox=box, resolution=0.05,
                         drop_flat_vertices=False)
    assert report["written"] and report["triangles"] == full.triangle_count


def test_meshing_options_are_one_table_with_real_signatures():
    names = [row["name"] for row in fc.mesh_settings_table()]
    assert names == ["mesher", "sharp_features", "drop_flat_vertices", "refine",
                     "refine_levels", "straighten_creases", "tolerance"]
    for method in (fc.Shape.mesh, fc.Shape.export):
        params = inspect.signature(method).parameters
        for row in fc.mesh_settings_table():
            assert params[row["name"]].default == row["default"]
            assert params[row["name"]].kind == inspect.Parameter.KEYWORD_ONLY
        assert "refine_levels" in method.__doc__
    defaults = fc.MeshSettings()
    assert defaults.to_dict() == {row["name"]: row["default"]
                                  for row in fc.mesh_settings_table()}
    assert repr(fc.MeshSettings(refine="tips")) == "MeshSettings(refine='tips')"
    with pytest.raises(TypeError, match="unknown meshing option 'sharpness'; allowed: mesher"):
        fc.mesh_settings(sharpness=True)
    with pytest.raises(ValueError, match="refine must be off, thin-parts or tips, got 'all'"):
        fc.MeshSettings(refine="all")
    assert fc.MeshSettings(refine_levels=2).problem() == (
        "refine_levels", "{refine_levels} 2 applies to a refinement: set {refine} to "
        "thin-parts or tips, or {refine_levels} to 1")


def test_node_functions_show_the_signature_they_take():
    b = fc.box((1, 2, 3), (4, 5, 6))
    assert b.params["size"] == (1, 2, 3) and b.params["corner"] == (4, 5, 6)
    assert list(inspect.signature(fc.box).parameters) == ["size", "corner"]
    for info in fc.node_types():
        function = getattr(fc, info["type"], None)
        if function is None:
            continue
        params = inspect.signature(function).parameters
        documented = [line.split()[0] for line in function.__doc__.split("Parameters:")[1]
                      .splitlines() if line.strip()]
        named = [n for n, p in params.items() if p.kind in (p.POSITIONAL_OR_KEYWORD,
                                                            p.KEYWORD_ONLY)]
        assert named == documented, info["type"]
        assert {p["name"] for p in info["params"]} == set(named), info["type"]
        for p in info["params"]:
            assert params[p["name"]].default == p["default"], (info["type"], p["name"])


def test_one_version_and_one_exit_status_table():
    with open(os.path.join(SOURCE, "Mod", "FRep", "package.xml"), encoding="utf-8") as f:
        assert "<version>%s</version>" % fc.__version__ in f.read()
    status = fc.EXIT_STATUS
    assert fc.exit_status_of(fc.NotPrintable("x", {})) == status["not_printable"] == 1
    assert fc.exit_status_of(fc.Cancelled("x")) == status["cancelled"] == 130
    assert fc.exit_status_of(KeyboardInterrupt()) == 130
    assert fc.exit_status_of(ValueError("x")) == fc.exit_status_of(OSError()) == 2
    assert fc.exit_status_of(KeyError("x")) == status["internal_error"] == 3
    # two balls that do not meet: nothing to print, which is a verdict (a ValueError too)
    with pytest.raises(fc.EmptySolid, match="the solid is empty") as empty:
        fc.automatic_box(fc.sphere(1) & fc.sphere(1, (9, 0, 0)))
    assert isinstance(empty.value, ValueError)
    assert fc.exit_status_of(empty.value) == status["not_printable"]


def test_older_keyword_spellings_still_mean_the_same_settings():
    older = fc.mesh_settings(sharp=False, fewer_triangles=False, refine_thin_parts=True,
                             refine_tips=True)
    assert older == fc.MeshSettings(sharp_features=False, drop_flat_vertices=False,
                                    refine="tips")
    assert fc.mesh_settings(refine_tips=True, refine_thin_parts=True).refine == "tips"
    part = csg()
    box = ((-1.2, -1.2, -1.2), (1.2, 1.2, 1.2))
    assert (part.mesh(0.1, bbox=box, sharp=False).triangle_count
            == part.mesh(0.1, bbox=box, sharp_features=False).triangle_count)


def test_hsplines_refine_edit_and_leave_as_step_stl_and_hs(tmp_path):
    h = fc.HSpline.torus(8, 6, 5, 1.5)
    before = h.evaluate(1.3, 2.7)["point"]
    h.refine(0, [(2, 2), (3, 2)])
    assert h.level_count == 2 and h.evaluate(1.3, 2.7)["point"] == pytest.approx(before, abs=1e-12)
    movable = h.select_movable(1)
    assert movable and all(h.movable(*c) for c in movable)
    level, i, j = movable[0]
    target = [x + 0.25 for x in h.position(level, i, j)]
    h.move_cv(level, i, j, target)
    assert h.position(level, i, j) == pytest.approx(target, abs=1e-12)
    with pytest.raises(ValueError, match="is fixed"):
        h.move_cv(1, *h.cvs(1)[0][1:], (0, 0, 0))
    # The flat arrays rebuild the same hierarchy (how the FreeCAD feature stores it).
    a = h.to_arrays()
    again = fc.HSpline.from_arrays(a["knots_u"], a["period_u"], a["knots_v"], a["period_v"],
                                   a["levels"], a["i"], a["j"], a["values"])
    assert again.to_text() == h.to_text()
    with pytest.raises(ValueError, match="lies outside level 1"):
        fc.HSpline.from_arrays(a["knots_u"], a["period_u"], a["knots_v"], a["period_v"],
                               a["levels"], [v if n != len(a["i"]) - 1 else 999
                                             for n, v in enumerate(a["i"])], a["j"], a["values"])
    path = str(tmp_path / "t.hs")
    h.write_hs(path)
    assert fc.read_hs(path).to_text() == h.to_text()
    step = str(tmp_path / "t.step")
    written = h.write_step(step)
    back = fc.read_step_summary(step)
    assert back["solids"] == 1 and back["valid"]
    assert back["volume"] == pytest.approx(written["volume"], rel=1e-9)
    report = h.tessellate(0.005).check()
    assert report["printable"] and report["outward"], report["text"]
    flat = h.bspline()
    assert flat["uperiodic"] and flat["vperiodic"]
    assert len(flat["poles"]) == sum(flat["umults"][:-1])


def test_a_cylinder_attaches_to_a_plane_through_a_catmull_clark_seam():
    plane = fc.HSpline.plane(10, 10, 90, 90)
    ring = ([(i, 3) for i in range(3, 6)] + [(6, j) for j in range(3, 6)] +
            [(i, 6) for i in range(6, 3, -1)] + [(3, j) for j in range(6, 3, -1)])
    at = [plane.position(0, i, j) for i, j in ring]
    cx, cy = sum(p[0] for p in at) / 12, sum(p[1] for p in at) / 12
    knots_v = [0, 0, 0, 0, 1, 2, 2, 2, 2]
    positions = [(cx + 0.7 * (p[0] - cx), cy + 0.7 * (p[1] - cy), 10.0 * (r - 1))
                 for r in range(5) for p in at]
    cylinder = fc.HSpline.from_grid(list(range(12)), 12.0, knots_v, 0.0, positions)
    a = fc.attach_cylinder(plane, 3, 6, 3, 6, cylinder, 3)
    assert a["extraordinary"] == 4 and a["boundary_loops"] == 2
    assert len(a["mesh"].triangles) > 4000
    with pytest.raises(ValueError, match="the ring around the rectangle has 14"):
        fc.attach_cylinder(plane, 3, 7, 3, 6, cylinder, 3)


def test_file_paths_are_str_or_path_like_and_never_cut_at_a_nul(tmp_path):
    ball = fc.sphere(1)
    target = tmp_path / "ball.stl"  # a pathlib.Path, as open() takes it
    assert ball.export(target, cells=16)["written"]
    assert fc.read_mesh(target).triangle_count > 0
    shape, settings = fc.load(pathlib.Path(SOURCE, "examples") / "sphere.json")
    assert settings["resolution"] > 0
    lattice = fc.read_lattice(pathlib.Path(SOURCE, "examples") / "lattices" / "bend.json")
    lattice.write(tmp_path / "bend.json")
    assert fc.read_lattice(str(tmp_path / "bend.json")).to_json() == lattice.to_json()
    # the C library would stop at the NUL and write "cut"
    with pytest.raises(ValueError, match="a file name cannot hold a NUL character"):
        ball.export(str(tmp_path / "cut\0.stl"), cells=16)
    with pytest.raises(ValueError, match="NUL"):
        fc.read_mesh(str(target) + "\0.obj")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ball.stl", "bend.json"]
    with pytest.raises(TypeError, match=r"str \| os.PathLike"):
        fc.read_mesh(3)


def test_searches_and_boxes_that_mean_nothing_are_refused():
    ball = fc.sphere(1)
    for search in (math.nan, 0, -1, math.inf):
        with pytest.raises(ValueError, match="bounds: search = .* must be a finite half-width"):
            ball.bounds(search=search)
    with pytest.raises(ValueError, match="tolerance"):
        ball.bounds(tolerance=math.nan)
    with pytest.raises(ValueError, match="interval: lo y = 1 is not <= hi y = -1"):
        ball.interval((0, 1, 0), (1, -1, 1))
    lo, hi = ball.interval((-2, -2, -2), (2, 2, 2))
    assert lo <= ball(0, 0, 0) <= hi
