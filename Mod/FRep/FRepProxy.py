"""Base of every proxy of the workbench (features and view providers): it saves nothing.
A feature's state is its properties, so a document reopens from them alone."""


class StatelessProxy:
    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None

    # FreeCAD 0.21+ calls these instead of the two above.
    def dumps(self):
        return None

    def loads(self, state):
        return None


def add_property(obj, kind, name, group, doc, value=None):
    """Adds a property unless the object has it (a reopened document keeps its values)."""
    if name not in obj.PropertiesList:
        obj.addProperty(kind, name, group, doc)
        if value is not None:
            setattr(obj, name, value)


class FeatureProxy(StatelessProxy):
    """Base of the workbench's document features: setup(obj) adds the properties, both when
    the feature is made and when a document saved before a property existed is reopened."""

    def __init__(self, obj):
        obj.Proxy = self
        self.setup(obj)

    def onDocumentRestored(self, obj):
        self.setup(obj)
