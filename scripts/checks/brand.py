"""Brand images: Home Assistant's brands rules for the integration's brand/ folder."""

from dataclasses import dataclass
from pathlib import Path
import struct
from typing import Final

from PIL import Image

BRAND_IMAGES: Final = frozenset(
    {
        "icon.png",
        "icon@2x.png",
        "logo.png",
        "logo@2x.png",
        "dark_icon.png",
        "dark_icon@2x.png",
        "dark_logo.png",
        "dark_logo@2x.png",
    }
)
REQUIRED_BRAND_IMAGES: Final = ("icon.png", "icon@2x.png", "logo.png", "logo@2x.png")
PNG_SIGNATURE: Final = b"\x89PNG\r\n\x1a\n"
# PNG colour types with an alpha channel: grey + alpha, RGBA.
PNG_ALPHA_TYPES: Final = frozenset({4, 6})


@dataclass(frozen=True, slots=True)
class PngHeader:
    """The IHDR facts of a PNG file."""

    width: int
    height: int
    colour_type: int


def png_header(data: bytes) -> PngHeader | None:
    """Width, height and colour type from a PNG's IHDR chunk, or None if not a PNG."""
    if len(data) < 33 or not data.startswith(PNG_SIGNATURE) or data[12:16] != b"IHDR":
        return None
    width, height, _depth, colour_type = struct.unpack(">IIBB", data[16:26])
    return PngHeader(width, height, colour_type)


def brand_problems(directory: Path) -> list[str]:
    """Missing, unknown, wrongly sized, opaque or untrimmed brand images."""
    present = (
        {path.name for path in directory.iterdir()} if directory.is_dir() else set()
    )
    problems = [
        f"{name} is missing" for name in REQUIRED_BRAND_IMAGES if name not in present
    ]
    problems += [
        f"{name} is not a brand image name" for name in sorted(present - BRAND_IMAGES)
    ]
    headers: dict[str, PngHeader] = {}
    for name in sorted(present & BRAND_IMAGES):
        header = png_header((directory / name).read_bytes())
        if header is None:
            problems.append(f"{name} is not a PNG")
            continue
        headers[name] = header
        problems += _brand_image_problems(name, header, directory / name)
    for name, header in headers.items():
        single = headers.get(name.replace("@2x", ""))
        if (
            "@2x" in name
            and single is not None
            and (
                abs(header.width - 2 * single.width) > 1
                or abs(header.height - 2 * single.height) > 1
            )
        ):
            problems.append(
                f"{name} is not twice the size of {name.replace('@2x', '')}"
            )
    return problems


def _brand_image_problems(name: str, header: PngHeader, path: Path) -> list[str]:
    problems: list[str] = []
    scale = 2 if "@2x" in name else 1
    size = f"{header.width}x{header.height}"
    if "icon" in name and (header.width, header.height) != (256 * scale, 256 * scale):
        problems.append(f"{name} is {size}, not {256 * scale}x{256 * scale}")
    if "logo" in name:
        shortest = min(header.width, header.height)
        if not 128 * scale <= shortest <= 256 * scale:
            problems.append(
                f"{name} is {size}; its shortest side must be {128 * scale}-{256 * scale} px"
            )
        if header.width < header.height:
            problems.append(f"{name} is {size}, not landscape")
    if header.colour_type not in PNG_ALPHA_TYPES:
        problems.append(f"{name} has no alpha channel")
        return problems
    with Image.open(path) as image:
        alpha = image.convert("RGBA").getchannel("A")
    low, _high = alpha.getextrema()
    if low != 0:
        problems.append(f"{name} has no transparent background")
    bbox = alpha.getbbox() or (0, 0, 0, 0)
    # Trimmed: the artwork reaches both edges along at least one axis (1 px slack
    # for antialiasing).
    spans_width = bbox[0] <= 1 and bbox[2] >= header.width - 1
    spans_height = bbox[1] <= 1 and bbox[3] >= header.height - 1
    if not (spans_width or spans_height):
        problems.append(f"{name} is not trimmed: artwork spans {bbox} of {size}")
    return problems
