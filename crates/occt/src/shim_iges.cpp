// The IGES half of the shim: the only code that names OCCT's IGES toolkits
// (TKIGES and, through it, TKBool, TKBO, TKPrim). build.rs links it into a
// shared object of its own, which the Rust side embeds and shim.cpp loads
// with dlopen on the first IGES read or write (`iges_functions`). A process
// that reads STEP or BREP only then never loads those toolkits: the dynamic
// loader binds about a quarter fewer symbols at every start (the OCCT
// libraries are linked BIND_NOW, so each loaded one costs its whole symbol
// table at start; BENCHMARKS.md, session of 2026-12-07, ninth).
//
// Rules: plain C entry points; the objects made here are used and freed by
// shim.cpp through their base classes (same OCCT libraries, same C++
// runtime); no exception is caught here (shim.cpp's callers catch them).

#include <IGESControl_Reader.hxx>
#include <IGESControl_Writer.hxx>
#include <TopoDS_Shape.hxx>
#include <XSControl_Reader.hxx>

extern "C" {

/// A new IGES reader, seen as its base class (ReadFile, TransferRoots and
/// the work session are XSControl_Reader's; the IGES behaviour comes from
/// the constructor and the virtual NbRootsForTransfer).
XSControl_Reader* quadrille_iges_reader_new() { return new IGESControl_Reader(); }

/// Frees a reader made by quadrille_iges_reader_new.
void quadrille_iges_reader_free(XSControl_Reader* r) { delete static_cast<IGESControl_Reader*>(r); }

/// Writes `shape` as IGES (millimetres, B-rep mode, so edges stay shared)
/// to `path`; 1 on success, 0 when the writer failed.
int quadrille_iges_write(const TopoDS_Shape* shape, const char* path) {
  IGESControl_Writer w("MM", 1);
  return (w.AddShape(*shape) && (w.ComputeModel(), w.Write(path))) ? 1 : 0;
}

}  // extern "C"
