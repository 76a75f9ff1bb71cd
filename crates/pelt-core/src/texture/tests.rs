//! Tests of the texture module: the mipmaps and the atlas against references computed here from
//! their definitions, and the image views' checks.

mod atlas;
mod image;
mod mip;
mod read;
