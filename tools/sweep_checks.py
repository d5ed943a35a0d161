"""What the "General parameters" generators (tools/make_general_blocks.py,
tools/make_general_rolling.py) share: the override that tilts gravity by theta, so that "down the
plane" is +x on a level plane, and the TOML text of one [[check]] (docs/case-file.md)."""
import math

G = 9.81


def tilted_gravity(theta):
    """The --set that turns gravity by theta degrees: [g sin(theta), -g cos(theta)]."""
    t = math.radians(theta)
    return f"simulation.gravity=[{G * math.sin(t):.12g}, {-G * math.cos(t):.12g}]"


def check_text(name, sets, body, time, against, known_miss=""):
    """One [[check]] of a body's displacement along +x at `time`, preceded by a blank line;
    `against`: its reference lines (reference and tolerance, or min and max, and the source)."""
    lines = ["", "[[check]]", f'name = "{name}"',
             "set = [" + ", ".join(f'"{s}"' for s in sets) + "]",
             f'quantity = "body.{body}.displacement"', "direction = [1.0, 0.0]", f"time = {time:g}"]
    lines += against
    if known_miss:
        lines.append(f'known_miss = "{known_miss}"')
    return "\n".join(lines)
