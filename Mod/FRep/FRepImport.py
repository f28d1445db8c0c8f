"""Opens FRepCAD JSON models (the format `frepcad export` reads) and HyperFun programs as FRep
features: File > Open and File > Import offer "FRep model (*.json)", "HyperFun model (*.hf)"
(docs/hyperfun.md: each library primitive a Formula feature with HyperFun's own expression,
the set operations and blends their features), and "OpenVDB volume (*.vdb)", which adds a
VdbGrid feature showing the file's first float or double grid (its Grid property picks
another). Each node becomes the feature of its registry
type with its parameters, the inputs linked and hidden, so the model can be edited like one
built from the toolbar. The model's description goes to the document's comment.

Scripting: FRepImport.import_model("examples/helix.json", doc) returns the top feature.
"""

import io
import os

import FreeCAD

import FRepFeatures as F
from FRepPaths import frepcore

FILTER = "FRep model (*.json)"
HYPERFUN_FILTER = "HyperFun model (*.hf)"
VDB_FILTER = "OpenVDB volume (*.vdb)"


def import_vdb(path, doc):
    """Adds a VdbGrid feature for the first scalar grid of a .vdb file; returns it."""
    grids = frepcore.vdb_grids(path)
    scalar = [g for g in grids if g["value_type"] in ("float", "double")]
    if not scalar:
        raise ValueError("%s: no float or double grid to show; the file's grids: %s"
                         % (path, ", ".join(g["text"] for g in grids) or "none"))
    obj = F.make("vdb_grid", doc, path=os.path.abspath(path), grid=scalar[0]["name"])
    obj.Label = "%s %s" % (os.path.splitext(os.path.basename(path))[0], scalar[0]["name"])
    return obj


def import_model(path, doc):
    """Adds the model's tree to doc as features; returns the feature of its root."""
    with io.open(path, encoding="utf-8") as f:  # this module's open() is FreeCAD's hook
        text = f.read()
    if path.lower().endswith(".hf"):
        model = frepcore.parse_hyperfun(text, os.path.basename(path))
    else:
        model = frepcore.parse_model(text, path, os.path.dirname(os.path.abspath(path)))
    return add_model(model, doc, os.path.splitext(os.path.basename(path))[0])


def add_model(model, doc, label):
    """Adds a parsed model (frepcore.parse_model's dict) to doc as features; returns the
    feature of its root, labelled `label`."""
    made = {}  # a node shared by several parents (the format allows it) becomes one feature
    labels = model.get("labels", {})  # a HyperFun program's names for its values

    def feature(node):
        key = node.to_json()
        if key not in made:
            inputs = [feature(i) for i in node.inputs]
            made[key] = F.make(node.type, doc, inputs=inputs, **node.params)
            if key in labels:
                made[key].Label = labels[key]
        return made[key]

    top = feature(model["root"])
    top.Label = label
    if model.get("description") and not doc.Comment:
        doc.Comment = model["description"]
    return top


def open(filename):  # noqa: A001  (FreeCAD's import-module interface)
    name = os.path.splitext(os.path.basename(filename))[0]
    doc = FreeCAD.newDocument(name)
    insert(filename, doc.Name)
    return doc


def insert(filename, docname):
    doc = FreeCAD.getDocument(docname)
    try:
        if filename.lower().endswith(".vdb"):
            import_vdb(filename, doc)
        else:
            import_model(filename, doc)
    except (ValueError, OSError) as e:
        FreeCAD.Console.PrintError("FRep import: %s\n" % e)
        raise
    doc.recompute()
