shapegen::generator! {
    struct G;
    shapes: [cube];
    node A { |s| {} }
}
fn main() {}
