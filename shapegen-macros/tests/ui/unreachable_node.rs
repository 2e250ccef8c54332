shapegen::generator! {
    struct G;
    shapes: [cube];
    start: A;
    node A { |s| {} }
    node Island { slots { back: A = 0.5 } |s| {} }
}
fn main() {}
