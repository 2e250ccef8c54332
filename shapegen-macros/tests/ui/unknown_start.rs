shapegen::generator! {
    struct G;
    shapes: [cube];
    start: Nope;
    node A { |s| {} }
}
fn main() {}
