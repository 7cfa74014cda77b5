"""The error a harness input file (a scene, a study) raises for a field it does not allow."""


class FieldError(ValueError):
    """`<source>: <name> = <value> is not allowed: <rule>`: the file, the field, its value and the
    rule, each also kept as an attribute."""

    def __init__(self, source, name, value, allowed):
        self.source, self.name, self.value, self.allowed = source, name, value, allowed
        super().__init__(f"{source}: {name} = {value!r} is not allowed: {allowed}")
