"""Stub of the FreeCAD module, as much of it as a post processor imports: no GUI, and
Units.Quantity for feed rates (FreeCAD keeps them in mm/s; posts write mm/min)."""
GuiUp = False


class _Units:
    Velocity = "Velocity"

    class Quantity:
        def __init__(self, value, unit):
            self.value = value

        def getValueAs(self, unit):
            return self.value * 60.0 if unit == "mm/min" else self.value * 60.0 / 25.4


Units = _Units
