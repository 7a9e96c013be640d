"""The one shared module that knows both geometries: which room a case
document, a case or a model belongs to, and that room's parts.  Everything
else shared asks here (docs/architecture.md); the rooms' modules load
when first asked for.

A room offers, in ``<room>/parts.py``: ``run_parts(case, comm)`` (the
model, loads, solver and energy book of a run), ``describe(case, model,
output)`` and ``dry_run(case, output)`` (the model summary); in
``<room>/schema.py``: ``read_start(chk, doc)`` and ``read_rest(chk, doc,
parts)`` (its tables); in ``<room>/layout.py``: what its models write
into a result file."""


def schema(doc):
    """The schema module of the room of a case document."""
    from vstpetsc.plane import schema as plane_schema
    if plane_schema.is_plane(doc):
        return plane_schema
    from vstpetsc.line import schema as line_schema
    return line_schema


def room(case):
    """The parts module of ``case``'s room."""
    if case.plane is not None:
        from vstpetsc.plane import parts as plane_parts
        return plane_parts
    from vstpetsc.line import parts as line_parts
    return line_parts


def layout(model):
    """The layout module of ``model``'s room."""
    if getattr(model, "dimension", 1) == 2:
        from vstpetsc.plane import layout as plane_layout
        return plane_layout
    from vstpetsc.line import layout as line_layout
    return line_layout
