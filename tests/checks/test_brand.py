"""brand_problems: sizes, transparency, trimming and names of brand images."""

from pathlib import Path

from PIL import Image

from scripts.checks.brand import PngHeader, brand_problems, png_header


def _png(
    path: Path,
    size: tuple[int, int],
    *,
    mode: str = "RGBA",
    box: tuple[int, int, int, int] | None = None,
) -> None:
    image = Image.new(mode, size)
    fill = (30, 90, 160, 255) if mode == "RGBA" else (30, 90, 160)
    image.paste(fill, box or (0, 0, *size))
    image.save(path)


def test_checker_png_header_is_read_without_decoding(tmp_path: Path) -> None:
    _png(tmp_path / "a.png", (300, 120))
    assert png_header((tmp_path / "a.png").read_bytes()) == PngHeader(300, 120, 6)
    assert png_header(b"GIF89a" + bytes(40)) is None


def test_checker_brand_images_must_have_the_right_sizes_and_transparency(
    tmp_path: Path,
) -> None:
    _png(tmp_path / "icon.png", (256, 256), box=(0, 40, 256, 216))
    _png(tmp_path / "icon@2x.png", (512, 512), box=(0, 80, 512, 432))
    _png(tmp_path / "logo.png", (400, 128), box=(0, 0, 400, 100))
    _png(tmp_path / "logo@2x.png", (800, 256), box=(0, 0, 800, 200))
    assert brand_problems(tmp_path) == []

    _png(tmp_path / "icon.png", (200, 200), mode="RGB")
    _png(tmp_path / "icon@2x.png", (512, 512), box=(10, 10, 500, 500))
    _png(tmp_path / "logo@2x.png", (256, 300))
    (tmp_path / "logo.png").unlink()
    (tmp_path / "banner.png").write_bytes(b"not a png")
    assert brand_problems(tmp_path) == [
        "logo.png is missing",
        "banner.png is not a brand image name",
        "icon.png is 200x200, not 256x256",
        "icon.png has no alpha channel",
        "icon@2x.png is not trimmed: artwork spans (10, 10, 500, 500) of 512x512",
        "logo@2x.png is 256x300, not landscape",
        "logo@2x.png has no transparent background",
        "icon@2x.png is not twice the size of icon.png",
    ]
