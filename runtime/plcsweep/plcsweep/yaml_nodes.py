"""YAML read as PyYAML's node tree, which keeps each value's line and column:
every error in a campaign names `file:line:column`, as plcrun's config
loader does (runtime/src/cell_config.cpp)."""

import yaml

# libyaml's loader and dumper where Debian's python3-yaml has them (it does):
# the same nodes and marks, several times faster for thousands of scenarios.
Loader = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
Dumper = getattr(yaml, "CSafeDumper", yaml.SafeDumper)


class CampaignError(Exception):
    """`file:line:column: message`; plcsweep exits with code 2."""

    def __init__(self, file, node_or_mark, message):
        line, col = 0, 0
        mark = getattr(node_or_mark, "start_mark", node_or_mark)
        if mark is not None and hasattr(mark, "line"):
            line, col = mark.line + 1, mark.column + 1
        super().__init__("%s:%d:%d: %s" % (file, line, col, message))
        self.file, self.line, self.column, self.message = file, line, col, message


def compose(text, file):
    try:
        return yaml.compose(text, Loader=Loader)
    except yaml.MarkedYAMLError as e:
        raise CampaignError(file, e.problem_mark, "YAML syntax error: %s" % e.problem) from None


def is_map(n):
    return isinstance(n, yaml.MappingNode)


def is_seq(n):
    return isinstance(n, yaml.SequenceNode)


def is_scalar(n):
    return isinstance(n, yaml.ScalarNode)


def items(n):
    """(key text, key node, value node) of a mapping node."""
    return [(k.value, k, v) for k, v in n.value]


def get(n, key):
    for k, v in n.value:
        if k.value == key:
            return v
    return None


def to_python(n):
    """Plain data (dict, list, str, int, float, bool, None) as YAML 1.1's
    safe loader types it."""
    return yaml.SafeLoader(  # constructs from the node, no re-parse
        "").construct_document(n) if n is not None else None


def scalar_node(value):
    """A plain scalar node for `value` (str, int, float, bool)."""
    if isinstance(value, bool):
        return yaml.ScalarNode("tag:yaml.org,2002:bool", "true" if value else "false")
    if isinstance(value, int):
        return yaml.ScalarNode("tag:yaml.org,2002:int", str(value))
    if isinstance(value, float):
        return yaml.ScalarNode("tag:yaml.org,2002:float", repr(value))
    return yaml.ScalarNode("tag:yaml.org,2002:str", str(value))


def dump(n):
    """The node tree as YAML text (key order kept)."""
    return yaml.serialize(n, Dumper=Dumper)
