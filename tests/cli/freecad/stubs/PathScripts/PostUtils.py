"""Stub: the editor dialog a post opens only when FreeCAD.GuiUp."""


class GCodeEditorDialog:
    def __init__(self):
        raise AssertionError("no GUI in the test: the editor dialog must not open")
