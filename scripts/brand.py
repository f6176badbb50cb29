"""Draw the integration's brand images into custom_components/tecoapi/brand/.

Original artwork for this project: a PLC module clipped on a DIN rail, its front
window showing a signal wave (the API). Run `scripts/run python scripts/brand.py`;
the output is deterministic, so re-running it leaves the committed PNGs unchanged
unless this script changed.

Home Assistant's brand rules: PNG with a transparent background, trimmed; icon
square 256x256 (icon@2x 512x512); logo's shortest side 128-256 px (logo@2x
256-512 px). The dark_ variants are used on dark themes.
"""

from collections.abc import Sequence
from dataclasses import dataclass
import math
from pathlib import Path
from typing import Final

from PIL import Image, ImageDraw, ImageFont

BRAND_DIR: Final = (
    Path(__file__).resolve().parent.parent / "custom_components" / "tecoapi" / "brand"
)

# Everything is drawn this many times larger, then reduced: cheap antialiasing.
SUPERSAMPLE: Final = 8
# The icon is designed on a 256-unit square.
DESIGN: Final = 256

type Colour = str
"""An opaque colour as Pillow reads it: "#RRGGBB"."""
type Box = tuple[float, float, float, float]
"""Left, top, right, bottom in design units."""
type Point = tuple[float, float]


@dataclass(frozen=True, slots=True, kw_only=True)
class Palette:
    """Flat colours of the artwork."""

    rail: Colour = "#8E9AA8"
    rail_shadow: Colour = "#6B7785"
    body: Colour = "#1F5FA8"
    body_edge: Colour = "#174A85"
    terminals: Colour = "#E8EDF3"
    screw: Colour = "#5B6B7D"
    window: Colour = "#0E2A4D"
    wave: Colour = "#3EE0A1"
    led_run: Colour = "#3EE0A1"
    led_comm: Colour = "#FFB547"
    wordmark: Colour = "#17304F"
    wordmark_accent: Colour = "#1F5FA8"


LIGHT: Final = Palette()
DARK: Final = Palette(wordmark="#F2F5F9", wordmark_accent="#5FA8F0")


class _Pen:
    """Draws in design units onto a supersampled canvas."""

    def __init__(self, draw: ImageDraw.ImageDraw, scale: float) -> None:
        self._draw = draw
        self._scale = scale

    def _box(self, box: Box) -> Box:
        s = self._scale
        x0, y0, x1, y1 = box
        return (x0 * s, y0 * s, x1 * s - 1, y1 * s - 1)

    def rounded(self, box: Box, radius: float, fill: Colour) -> None:
        """A filled rectangle with rounded corners."""
        self._draw.rounded_rectangle(
            self._box(box), radius=radius * self._scale, fill=fill
        )

    def circle(self, centre: Point, radius: float, fill: Colour) -> None:
        """A filled circle."""
        cx, cy = centre
        box = (cx - radius, cy - radius, cx + radius, cy + radius)
        self._draw.ellipse(self._box(box), fill=fill)

    def stroke(self, points: Sequence[Point], width: float, fill: Colour) -> None:
        """A polyline with round joints and caps."""
        s = self._scale
        scaled = [(x * s, y * s) for x, y in points]
        self._draw.line(scaled, fill=fill, width=round(width * s), joint="curve")
        for cap in (points[0], points[-1]):
            self.circle(cap, width / 2, fill)


def _draw_module(pen: _Pen, colours: Palette) -> None:
    """The PLC module on its rail, filling the 256-unit design square."""
    # DIN rail behind the module: a top-hat profile seen from the front.
    pen.rounded((0, 104, 256, 152), 8, colours.rail_shadow)
    pen.rounded((0, 104, 256, 140), 8, colours.rail)

    # Module housing, with a darker rim so it reads on light and dark themes.
    pen.rounded((36, 0, 220, 256), 28, colours.body_edge)
    pen.rounded((42, 6, 214, 250), 23, colours.body)

    # Terminal blocks at the top and bottom, four slotted screws each.
    for top in (20, 192):
        pen.rounded((56, top, 200, top + 44), 12, colours.terminals)
        for column in range(4):
            cx = 76 + column * 34.67
            pen.circle((cx, top + 22), 11, colours.screw)
            pen.stroke([(cx - 5, top + 27), (cx + 5, top + 17)], 4, colours.terminals)

    # Front window with one period of a wave: data to and from the PLC.
    pen.rounded((56, 76, 200, 150), 14, colours.window)
    wave = [
        (72 + step, 113 - 19 * math.sin(step / 112 * 2 * math.pi))
        for step in range(0, 113, 2)
    ]
    pen.stroke(wave, 11, colours.wave)

    # Status LEDs: run, run, communication.
    pen.circle((74, 172), 7, colours.led_run)
    pen.circle((102, 172), 7, colours.led_run)
    pen.circle((130, 172), 7, colours.led_comm)


def _supersampled(width: int, height: int) -> tuple[Image.Image, ImageDraw.ImageDraw]:
    canvas = Image.new("RGBA", (width * SUPERSAMPLE, height * SUPERSAMPLE))
    return canvas, ImageDraw.Draw(canvas)


def draw_icon(size: int, colours: Palette = LIGHT) -> Image.Image:
    """The square icon, `size` pixels wide."""
    canvas, draw = _supersampled(size, size)
    _draw_module(_Pen(draw, size * SUPERSAMPLE / DESIGN), colours)
    return canvas.resize((size, size), Image.Resampling.LANCZOS)


def _trimmed(image: Image.Image) -> Image.Image:
    bbox = image.getchannel("A").getbbox()
    assert bbox is not None
    return image.crop(bbox)


def draw_logo(height: int, colours: Palette = LIGHT) -> Image.Image:
    """The icon followed by the "PLC Bridge" wordmark, `height` pixels tall."""
    scale = height * SUPERSAMPLE / DESIGN
    # Pillow's built-in scalable font, so the result does not depend on the host.
    font = ImageFont.load_default(size=round(150 * scale))
    # Aileron has one weight; a stroke of the same colour makes it semibold, and
    # tracking keeps the thickened letters apart.
    weight = round(4 * scale)
    tracking = 6 * scale
    gap = round(44 * scale)
    icon_width = round(DESIGN * scale)

    letters = [(letter, colours.wordmark) for letter in "PLC "]
    letters += [(letter, colours.wordmark_accent) for letter in "Bridge"]
    probe = ImageDraw.Draw(Image.new("RGBA", (1, 1)))
    advances = [probe.textlength(letter, font=font) + tracking for letter, _ in letters]
    canvas = Image.new(
        "RGBA",
        (icon_width + gap + math.ceil(sum(advances)) + weight, round(DESIGN * scale)),
    )
    draw = ImageDraw.Draw(canvas)
    _draw_module(_Pen(draw, scale), colours)

    x = float(icon_width + gap + weight)
    for (letter, colour), advance in zip(letters, advances, strict=True):
        draw.text(
            (x, canvas.height / 2),
            letter,
            font=font,
            fill=colour,
            anchor="lm",
            stroke_width=weight,
            stroke_fill=colour,
        )
        x += advance

    logo = _trimmed(canvas)
    reduced = (
        round(logo.width / SUPERSAMPLE),
        round(logo.height / SUPERSAMPLE),
    )
    return logo.resize(reduced, Image.Resampling.LANCZOS)


def main() -> None:
    """Write every brand image."""
    BRAND_DIR.mkdir(parents=True, exist_ok=True)
    images = {
        "icon.png": draw_icon(256),
        "icon@2x.png": draw_icon(512),
        "logo.png": draw_logo(128),
        "logo@2x.png": draw_logo(256),
        "dark_logo.png": draw_logo(128, DARK),
        "dark_logo@2x.png": draw_logo(256, DARK),
    }
    for name, image in images.items():
        image.save(BRAND_DIR / name, optimize=True)
        print(f"{name}: {image.width}x{image.height}")


if __name__ == "__main__":
    main()
