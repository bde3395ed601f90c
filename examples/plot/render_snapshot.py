#!/usr/bin/python3
"""A snapshot of a contact-sim run as a PNG, 2D or 3D, rendered with VTK off screen
(contact.vtu.render: the body coloured by a field, its edges, the obstacle, a colour bar
and the time). Needs the contact package (PYTHONPATH=build/python) and python3-vtk9; with
no X display it starts a virtual one (Xvfb, Debian: xvfb).

  render_snapshot.py RUN_DIR|SNAPSHOT.vtu OUT.png [--magnify M] [--field F]
                     [--view X Y Z] [--size W H]

Given a run's output directory it draws the moment in contact: the snapshot of
solution.pvd's series with the largest sum of contact forces (contact.vtu.in_contact).
Prints the snapshot it drew, the picture's path and where the body is in it.
"""
import argparse
import os

import contact.vtu


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("source", help="a contact-sim output directory or one .vtu snapshot")
    parser.add_argument("out", help="the PNG to write")
    parser.add_argument("--magnify", type=float, default=1.0,
                        help="draw the body at x + MAGNIFY u (default 1: true scale)")
    parser.add_argument("--field", default="von_mises",
                        help="point or cell array to colour by (default von_mises)")
    parser.add_argument("--view", type=float, nargs=3, default=None,
                        help="direction the camera looks along")
    parser.add_argument("--size", type=int, nargs=2, default=[1200, 800], help="pixels")
    args = parser.parse_args()
    snapshot = contact.vtu.in_contact(args.source) if os.path.isdir(args.source) else args.source
    picture = contact.vtu.render(snapshot, args.out, magnify=args.magnify, field=args.field,
                                 size=tuple(args.size), view=args.view)
    print(f"snapshot {snapshot}")
    print(f"picture {picture.path}, the body in pixels (left, top, right, bottom) "
          f"{' '.join(f'{v:.0f}' for v in picture.body_box)}")


if __name__ == "__main__":
    main()
