// Flat C interface over the parts of OpenCASCADE 7.6 that Quadrille uses.
//
// Rules of this file:
// - Only opaque pointers and plain C data cross the boundary.
// - Every exported function catches every C++ exception (Standard_Failure and
//   anything else) and turns it into an error code: nothing unwinds into Rust.
// - Reading and writing files run with OCCT's signal handlers
//   (`SignalsAsExceptions`, `OCC_CATCH_SIGNALS`): OCCT's data-exchange
//   readers dereference null entities of malformed files (the fuzzer finds
//   them by the dozen), and the access violation becomes an error, not a dead
//   process. The process's own handlers are back when the call returns.
// - Reading a file is serialised by a global mutex (the OCCT data-exchange
//   readers keep global state); evaluating geometry is not (Geom_* evaluation
//   is const and cache-free in OCCT >= 7.2, so concurrent calls are safe).

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepTools.hxx>
#include <BRepTools_WireExplorer.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <GeomAPI_ProjectPointOnCurve.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <Geom2d_Curve.hxx>
#include <Geom_Curve.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Geom_Surface.hxx>
#include <Interface_Static.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Shell.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Check.hxx>
#include <Interface_CheckIterator.hxx>
#include <XSControl_Reader.hxx>
#include <XSControl_WorkSession.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Writer.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <STEPControl_Reader.hxx>
#include <OSD.hxx>
#include <Standard_ErrorHandler.hxx>
#include <Standard_Failure.hxx>
#include <TopAbs.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <TopoDS_Vertex.hxx>
#include <TopoDS_Wire.hxx>
#include <gp_Pnt.hxx>
#include <gp_Pnt2d.hxx>
#include <gp_Vec.hxx>
#include <gp_Vec2d.hxx>

#include <csignal>
#include <dlfcn.h>
#include <sys/mman.h>
#include <unistd.h>
#include <cstdlib>
#include <pthread.h>
#include <cstdio>
#include <cstring>
#include <memory>
#include <exception>
#include <atomic>
#include <mutex>
#include <string>
#include <vector>

// Error codes shared with src/ffi.rs.
enum {
  OK = 0,
  ERR_OPEN = 1,       // the reader could not open or parse the file
  ERR_TRANSFER = 2,   // parsed, but no shape could be built from it
  ERR_EXCEPTION = 3,  // OCCT threw; the message is in the error buffer
  ERR_INDEX = 4,      // an index out of range
  ERR_NULL = 5,       // a null geometry (e.g. an edge without a 3D curve)
  ERR_FAILED = 6,     // an algorithm ran but found no answer
  ERR_SMALL = 7,      // a caller buffer is too small
};

struct OcctModel {
  TopoDS_Shape shape;
  TopTools_IndexedMapOfShape faces, edges, vertices;
};
struct OcctSurf {
  Handle(Geom_Surface) s;
};
struct OcctCurve {
  Handle(Geom_Curve) c;
};
struct OcctCurve2d {
  Handle(Geom2d_Curve) c;
};

/// Information on one edge, filled by occt_edge.
struct OcctEdgeInfo {
  double first, last;   // parameter range of the edge
  double tolerance;     // BRep_Tool::Tolerance
  long v_start, v_end;  // 0-based vertex indices of the FORWARD edge; -1 if absent
  int degenerate;       // BRep_Tool::Degenerated
  int same_parameter;   // BRep_Tool::SameParameter
};

/// One B-spline patch for occt_write_bspline_step: distinct knots with
/// multiplicities in each direction, poles row-major with u fastest
/// (pole (i, j) at poles[3 * (j * n_u + i)]). Checked by the Rust caller.
struct OcctBSplinePatch {
  int degree_u, degree_v;
  size_t n_u, n_v;            // poles along u and v
  const double* knots_u;      // nk_u distinct knots
  const int* mults_u;
  size_t nk_u;
  const double* knots_v;
  const int* mults_v;
  size_t nk_v;
  const double* poles;        // 3 * n_u * n_v
};

/// What occt_write_bspline_step built, before writing.
struct OcctSewReport {
  size_t faces;         // faces in the written shape
  size_t shells;        // shells in it
  size_t free_edges;    // non-degenerate edges bounding one face
  size_t shared_edges;  // edges bounding two faces
  size_t multiple_edges;  // edges bounding three faces or more
};

/// One edge use in a face wire, filled by occt_face_uses.
struct OcctUse {
  long wire;            // 0 = outer wire, then holes in explorer order
  long edge;            // 0-based edge index
  int orientation;      // TopAbs_Orientation of the edge in the FORWARD face
  int seam;             // BRep_Tool::IsClosed(edge, face)
  double first, last;   // parameter range of the pcurve
  OcctCurve2d* pcurve;  // owned by the caller (free with occt_curve2d_free); may be null
};

static std::recursive_mutex g_read_mutex;

static void set_err(char* buf, size_t len, const std::string& msg) {
  if (buf == nullptr || len == 0) return;
  std::snprintf(buf, len, "%s", msg.c_str());
}

static std::string failure_text(const Standard_Failure& f) {
  std::string s = f.DynamicType()->Name();
  const char* m = f.GetMessageString();
  if (m != nullptr && *m != 0) {
    s += ": ";
    s += m;
  }
  return s;
}

// Runs `body`, converting exceptions to ERR_EXCEPTION (with text in err).
template <class F>
static int guarded(char* err, size_t errlen, F body) {
  try {
    return body();
  } catch (const Standard_Failure& f) {
    set_err(err, errlen, "OpenCASCADE exception " + failure_text(f));
  } catch (const std::exception& e) {
    set_err(err, errlen, std::string("C++ exception: ") + e.what());
  } catch (...) {
    set_err(err, errlen, "unknown C++ exception");
  }
  return ERR_EXCEPTION;
}

// Faults inside OCCT caught since the process started (every signal that
// reached OCCT's handlers through `counting_handler`, including those OCCT's
// own catch points recovered from inside a reader). A caught fault leaves
// OCCT's frames by a jump that skips their destructors and unlocks, so after
// one the process's OCCT and heap state can no longer be trusted: the Rust
// side refuses later reads (`occt::load`).
static std::atomic<unsigned long> g_faults_caught{0};
// OCCT's handler of each fault signal while a SignalsAsExceptions lives
// (written under g_read_mutex before the counting handler is installed).
static struct sigaction g_occt_actions[32];

// Counts the fault, then hands it to OCCT's handler, which jumps to the
// nearest OCC_CATCH_SIGNALS (this frame holds nothing to destroy).
static void counting_handler(int sig, siginfo_t* info, void* ctx) {
  g_faults_caught.fetch_add(1, std::memory_order_relaxed);
  const struct sigaction& a = g_occt_actions[sig];
  if (a.sa_flags & SA_SIGINFO) {
    a.sa_sigaction(sig, info, ctx);
  } else if (a.sa_handler != SIG_DFL && a.sa_handler != SIG_IGN) {
    a.sa_handler(sig);
  } else {
    signal(sig, SIG_DFL);
    raise(sig);
  }
}

// While alive: OCCT's signal handlers, which turn an access violation (or
// another fault) inside OCCT into a jump to the nearest OCC_CATCH_SIGNALS,
// where it is thrown as a Standard_Failure. The fault handlers run on an
// alternate stack of their own, so that a stack overflow (OCCT recursing on
// a reference cycle of a damaged file) is caught too: the jump leaves the
// exhausted stack behind. The handlers the process had (Rust's
// stack-overflow guard, Python's Ctrl-C), its alternate stack and its signal
// mask are put back.
class SignalsAsExceptions {
 public:
  SignalsAsExceptions() : alt_(ALT_STACK) {
    for (int s = 1; s < NSIG_SAVED; ++s) sigaction(s, nullptr, &saved_[s]);
    pthread_sigmask(SIG_SETMASK, nullptr, &mask_);
    stack_t ss;
    ss.ss_sp = alt_.data();
    ss.ss_size = alt_.size();
    ss.ss_flags = 0;
    have_alt_ = sigaltstack(&ss, &old_alt_) == 0;
    OSD::SetSignal(OSD_SignalMode_Set, Standard_False);
    // SA_NODEFER: the handler leaves by a jump, and OCCT's own catch points
    // inside the readers go on after it; without it the fault signal would
    // stay blocked and the next fault would kill the process
    // Each fault goes through counting_handler on its way to OCCT's handler
    for (int s : {SIGSEGV, SIGBUS, SIGFPE, SIGILL}) {
      struct sigaction a;
      if (sigaction(s, nullptr, &a) == 0) {
        g_occt_actions[s] = a;
        a.sa_sigaction = counting_handler;
        a.sa_flags |= SA_SIGINFO | SA_ONSTACK | SA_NODEFER;
        sigaction(s, &a, nullptr);
      }
    }
  }
  ~SignalsAsExceptions() {
    for (int s = 1; s < NSIG_SAVED; ++s) {
      if (s != SIGKILL && s != SIGSTOP) sigaction(s, &saved_[s], nullptr);
    }
    // the jump out of a handler leaves the fault signal blocked
    pthread_sigmask(SIG_SETMASK, &mask_, nullptr);
    if (have_alt_) sigaltstack(&old_alt_, nullptr);
  }
  SignalsAsExceptions(const SignalsAsExceptions&) = delete;
  SignalsAsExceptions& operator=(const SignalsAsExceptions&) = delete;

 private:
  static const int NSIG_SAVED = 32;
  static const size_t ALT_STACK = 256 * 1024;
  struct sigaction saved_[NSIG_SAVED];
  sigset_t mask_;
  std::vector<char> alt_;
  stack_t old_alt_;
  bool have_alt_ = false;
};

// OCCT's handlers are process-wide: one scope at a time (under the reader
// mutex, the one lock of this file, so no two locks can be taken in
// opposite orders), nested scopes of the same thread reuse the outer one.
static thread_local int t_signal_depth = 0;

class SignalScope {
 public:
  SignalScope() {
    if (t_signal_depth++ == 0) {
      g_read_mutex.lock();
      signals_.reset(new SignalsAsExceptions());
    }
  }
  ~SignalScope() {
    signals_.reset();
    if (--t_signal_depth == 0) g_read_mutex.unlock();
  }
  SignalScope(const SignalScope&) = delete;
  SignalScope& operator=(const SignalScope&) = delete;

 private:
  std::unique_ptr<SignalsAsExceptions> signals_;
};

// Runs `body` with faults inside OCCT converted to errors (see
// SignalsAsExceptions); nothing the jump skips may own a lock or need its
// destructor.
template <class F>
static int fault_guarded(char* err, size_t errlen, F body) {
  SignalScope signals;
  try {
    OCC_CATCH_SIGNALS
    return body();
  } catch (const Standard_Failure& f) {
    set_err(err, errlen, "OpenCASCADE failed on this file (" + failure_text(f) + ")");
  } catch (const std::exception& e) {
    set_err(err, errlen, std::string("C++ exception: ") + e.what());
  } catch (...) {
    set_err(err, errlen, "unknown C++ exception");
  }
  return ERR_EXCEPTION;
}

static void silence_messages() {
  static std::once_flag once;
  std::call_once(once, [] {
    const Handle(Message_Messenger)& m = Message::DefaultMessenger();
    if (!m.IsNull()) m->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));
  });
}

// After parsing: finds structural errors (unresolved references, entities of
// the wrong type, syntax errors) that leave null entities behind, on which
// OCCT's transfer dereferences null handles and crashes. Benign fails (an odd
// unit definition, …) are let through. Returns an empty string when fine.
static std::string structural_errors(XSControl_Reader& r) {
  Interface_CheckIterator it = r.WS()->ModelCheckList();
  int n = 0;
  std::string first;
  for (it.Start(); it.More(); it.Next()) {
    const Handle(Interface_Check)& c = it.Value();
    for (int k = 1; k <= c->NbFails(); ++k) {
      std::string msg = c->CFail(k);
      if (msg.find("nresolved") != std::string::npos || msg.find("Undefined") != std::string::npos ||
          msg.find("illegal type") != std::string::npos || msg.find("Parsing") != std::string::npos) {
        if (n++ == 0) first = msg;
      }
    }
  }
  if (n == 0) return std::string();
  return std::to_string(n) + " structural error(s) (unresolved references, bad syntax); the first: " + first;
}


// The IGES half of the shim (shim_iges.cpp), a shared object image embedded
// in the Rust crate and handed over by occt_iges_image before any IGES read
// or write. Loaded on first use: a process that reads no IGES never loads
// OCCT's IGES toolkits, and the dynamic loader binds about a quarter fewer
// symbols at its start.
struct IgesFunctions {
  XSControl_Reader* (*reader_new)();
  void (*reader_free)(XSControl_Reader*);
  int (*write)(const TopoDS_Shape*, const char*);
};
static std::atomic<const unsigned char*> g_iges_image{nullptr};
static std::atomic<size_t> g_iges_image_len{0};

// Writes the image to a file descriptor: an anonymous memory file, else a
// temporary file (unlinked at once, kept open). -1 when neither works.
static int iges_image_fd(const unsigned char* image, size_t len) {
  int fd = memfd_create("quadrille-occt-iges", MFD_CLOEXEC);
  if (fd < 0) {
    const char* dir = std::getenv("TMPDIR");
    std::string name = std::string(dir != nullptr && *dir != 0 ? dir : "/tmp") + "/quadrille-iges-XXXXXX";
    std::vector<char> buf(name.begin(), name.end());
    buf.push_back(0);
    fd = mkstemp(buf.data());
    if (fd < 0) return -1;
    unlink(buf.data());
  }
  size_t done = 0;
  while (done < len) {
    ssize_t k = ::write(fd, image + done, len - done);
    if (k <= 0) {
      close(fd);
      return -1;
    }
    done += (size_t)k;
  }
  return fd;
}

// The IGES functions, loaded once; null with the reason in `why` when the
// image is missing or cannot be loaded.
static const IgesFunctions* iges_functions(std::string& why) {
  static std::once_flag once;
  static IgesFunctions fns{nullptr, nullptr, nullptr};
  static std::string failure;
  std::call_once(once, [] {
    const unsigned char* image = g_iges_image.load();
    size_t len = g_iges_image_len.load();
    if (image == nullptr || len == 0) {
      failure = "the IGES part of the OCCT shim was not handed over";
      return;
    }
    int fd = iges_image_fd(image, len);
    if (fd < 0) {
      failure = "the IGES part of the OCCT shim could not be written to a file";
      return;
    }
    std::string path = "/proc/self/fd/" + std::to_string(fd);
    void* h = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    close(fd);
    if (h == nullptr) {
      const char* e = dlerror();
      failure = std::string("the IGES part of the OCCT shim could not be loaded: ") + (e ? e : "?");
      return;
    }
    IgesFunctions f;
    f.reader_new = reinterpret_cast<XSControl_Reader* (*)()>(dlsym(h, "quadrille_iges_reader_new"));
    f.reader_free = reinterpret_cast<void (*)(XSControl_Reader*)>(dlsym(h, "quadrille_iges_reader_free"));
    f.write = reinterpret_cast<int (*)(const TopoDS_Shape*, const char*)>(dlsym(h, "quadrille_iges_write"));
    if (f.reader_new == nullptr || f.reader_free == nullptr || f.write == nullptr) {
      failure = "the IGES part of the OCCT shim lacks its functions";
      return;
    }
    fns = f;
  });
  if (fns.reader_new == nullptr) {
    why = failure;
    return nullptr;
  }
  return &fns;
}

// Owns a reader made by the IGES part.
struct IgesReader {
  const IgesFunctions* f;
  XSControl_Reader* r;
  ~IgesReader() { f->reader_free(r); }
};

extern "C" {

/// Hands over the image of the IGES part (shim_iges.cpp as a shared object);
/// the bytes must live as long as the process. Later calls are ignored.
void occt_iges_image(const unsigned char* image, size_t len) {
  const unsigned char* none = nullptr;
  if (g_iges_image.compare_exchange_strong(none, image)) g_iges_image_len.store(len);
}

/// Reads a file. kind: 0 STEP, 1 IGES, 2 BREP. On success *out owns the model.
int occt_load(const char* path, int kind, OcctModel** out, char* err, size_t errlen) {
  if (out == nullptr) return ERR_INDEX;
  *out = nullptr;
  return guarded(err, errlen, [&]() -> int {
    TopoDS_Shape shape;
    {
      std::lock_guard<std::recursive_mutex> lock(g_read_mutex);
      silence_messages();
      int rc = fault_guarded(err, errlen, [&]() -> int {
      if (kind == 0 || kind == 1) {
        IFSelect_ReturnStatus st;
        if (kind == 0) {
          STEPControl_Reader r;
          st = r.ReadFile(path);
          if (st != IFSelect_RetDone) {
            set_err(err, errlen, "the STEP reader could not parse it (status " + std::to_string((int)st) + ")");
            return ERR_OPEN;
          }
          std::string bad = structural_errors(r);
          if (!bad.empty()) {
            set_err(err, errlen, bad);
            return ERR_OPEN;
          }
          r.TransferRoots();
          if (r.NbShapes() == 0) {
            set_err(err, errlen, "it holds no shape that OpenCASCADE can transfer");
            return ERR_TRANSFER;
          }
          shape = r.OneShape();
        } else {
          std::string why;
          const IgesFunctions* f = iges_functions(why);
          if (f == nullptr) {
            set_err(err, errlen, why);
            return ERR_OPEN;
          }
          IgesReader owned{f, f->reader_new()};
          XSControl_Reader& r = *owned.r;
          st = r.ReadFile(path);
          if (st != IFSelect_RetDone) {
            set_err(err, errlen, "the IGES reader could not parse it (status " + std::to_string((int)st) + ")");
            return ERR_OPEN;
          }
          std::string bad = structural_errors(r);
          if (!bad.empty()) {
            set_err(err, errlen, bad);
            return ERR_OPEN;
          }
          r.TransferRoots();
          if (r.NbShapes() == 0) {
            set_err(err, errlen, "it holds no shape that OpenCASCADE can transfer");
            return ERR_TRANSFER;
          }
          shape = r.OneShape();
        }
      } else if (kind == 2) {
        BRep_Builder b;
        if (!BRepTools::Read(shape, path, b)) {
          set_err(err, errlen, "the BREP reader could not parse it");
          return ERR_OPEN;
        }
      } else {
        return ERR_INDEX;
      }
      return OK;
      });
      if (rc != OK) return rc;
    }
    if (shape.IsNull()) {
      set_err(err, errlen, "it holds no shape that OpenCASCADE can transfer");
      return ERR_TRANSFER;
    }
    OcctModel* m = new OcctModel();
    m->shape = shape;
    TopExp::MapShapes(shape, TopAbs_FACE, m->faces);
    TopExp::MapShapes(shape, TopAbs_EDGE, m->edges);
    TopExp::MapShapes(shape, TopAbs_VERTEX, m->vertices);
    *out = m;
    return OK;
  });
}

void occt_model_free(OcctModel* m) { delete m; }

/// Faults inside OCCT become errors on this thread until occt_signals_end
/// (used around a whole import: reading, then the topology queries).
void* occt_signals_begin() { return new SignalScope(); }
void occt_signals_end(void* scope) { delete static_cast<SignalScope*>(scope); }

/// How many faults inside OCCT were caught in this process so far.
unsigned long occt_faults_caught() { return g_faults_caught.load(std::memory_order_relaxed); }

/// Writes the model's shape to `path`. kind: 0 STEP (AP214, as is), 1 IGES
/// (B-rep mode, so edges stay shared), 2 BREP.
int occt_write(const OcctModel* m, const char* path, int kind, char* err, size_t errlen) {
  return guarded(err, errlen, [&]() -> int {
    std::lock_guard<std::recursive_mutex> lock(g_read_mutex);
    silence_messages();
    return fault_guarded(err, errlen, [&]() -> int {
    bool ok = false;
    if (kind == 0) {
      STEPControl_Writer w;
      ok = w.Transfer(m->shape, STEPControl_AsIs) == IFSelect_RetDone && w.Write(path) == IFSelect_RetDone;
    } else if (kind == 1) {
      std::string why;
      const IgesFunctions* f = iges_functions(why);
      if (f == nullptr) {
        set_err(err, errlen, why);
        return ERR_FAILED;
      }
      ok = f->write(&m->shape, path) != 0;
    } else if (kind == 2) {
      ok = BRepTools::Write(m->shape, path);
    } else {
      return ERR_INDEX;
    }
    if (!ok) {
      set_err(err, errlen, "the writer failed");
      return ERR_FAILED;
    }
    return OK;
    });
  });
}

/// Builds one untrimmed face per B-spline patch (its natural bounds, four
/// edges), sews them with `sew_tol` into shells (a face sewing leaves alone
/// becomes a shell of its own), and writes them as STEP (AP214, as is) to
/// `path`. Fills *report; on failure no promise is made about `path`'s
/// content (the Rust caller writes to a temporary file).
int occt_write_bspline_step(const OcctBSplinePatch* patches, size_t n, double sew_tol, const char* path,
                            OcctSewReport* report, char* err, size_t errlen) {
  if (patches == nullptr || report == nullptr || n == 0) return ERR_INDEX;
  *report = OcctSewReport{0, 0, 0, 0, 0};
  return guarded(err, errlen, [&]() -> int {
    std::lock_guard<std::recursive_mutex> lock(g_read_mutex);
    silence_messages();
    return fault_guarded(err, errlen, [&]() -> int {
      BRepBuilderAPI_Sewing sewing(sew_tol);
      for (size_t k = 0; k < n; ++k) {
        const OcctBSplinePatch& p = patches[k];
        TColgp_Array2OfPnt poles(1, (int)p.n_u, 1, (int)p.n_v);
        for (size_t j = 0; j < p.n_v; ++j)
          for (size_t i = 0; i < p.n_u; ++i) {
            const double* x = p.poles + 3 * (j * p.n_u + i);
            poles.SetValue((int)i + 1, (int)j + 1, gp_Pnt(x[0], x[1], x[2]));
          }
        TColStd_Array1OfReal ku(1, (int)p.nk_u), kv(1, (int)p.nk_v);
        TColStd_Array1OfInteger mu(1, (int)p.nk_u), mv(1, (int)p.nk_v);
        for (size_t i = 0; i < p.nk_u; ++i) {
          ku.SetValue((int)i + 1, p.knots_u[i]);
          mu.SetValue((int)i + 1, p.mults_u[i]);
        }
        for (size_t i = 0; i < p.nk_v; ++i) {
          kv.SetValue((int)i + 1, p.knots_v[i]);
          mv.SetValue((int)i + 1, p.mults_v[i]);
        }
        Handle(Geom_BSplineSurface) surf =
            new Geom_BSplineSurface(poles, ku, kv, mu, mv, p.degree_u, p.degree_v);
        BRepBuilderAPI_MakeFace mf(surf, sew_tol);
        if (!mf.IsDone()) {
          set_err(err, errlen, "patch " + std::to_string(k) + ": no face could be built on it (BRepBuilderAPI_MakeFace error " +
                                   std::to_string((int)mf.Error()) + ")");
          return ERR_FAILED;
        }
        sewing.Add(mf.Face());
      }
      sewing.Perform();
      TopoDS_Shape sewn = sewing.SewedShape();
      if (sewn.IsNull()) {
        set_err(err, errlen, "sewing gave no shape");
        return ERR_FAILED;
      }
      // Shells as they are; a face left on its own becomes a one-face shell.
      BRep_Builder b;
      std::vector<TopoDS_Shape> shells;
      for (TopExp_Explorer x(sewn, TopAbs_SHELL); x.More(); x.Next()) shells.push_back(x.Current());
      for (TopExp_Explorer x(sewn, TopAbs_FACE, TopAbs_SHELL); x.More(); x.Next()) {
        TopoDS_Shell sh;
        b.MakeShell(sh);
        b.Add(sh, x.Current());
        shells.push_back(sh);
      }
      TopoDS_Shape out;
      if (shells.size() == 1) {
        out = shells[0];
      } else {
        TopoDS_Compound c;
        b.MakeCompound(c);
        for (const TopoDS_Shape& sh : shells) b.Add(c, sh);
        out = c;
      }
      TopTools_IndexedMapOfShape faces;
      TopExp::MapShapes(out, TopAbs_FACE, faces);
      TopTools_IndexedDataMapOfShapeListOfShape edge_faces;
      TopExp::MapShapesAndUniqueAncestors(out, TopAbs_EDGE, TopAbs_FACE, edge_faces);
      report->faces = (size_t)faces.Extent();
      report->shells = shells.size();
      for (int i = 1; i <= edge_faces.Extent(); ++i) {
        if (BRep_Tool::Degenerated(TopoDS::Edge(edge_faces.FindKey(i)))) continue;
        int nf = edge_faces(i).Extent();
        if (nf == 1) ++report->free_edges;
        else if (nf == 2) ++report->shared_edges;
        else if (nf > 2) ++report->multiple_edges;
      }
      // AP214 for this file only: the schema is a global setting
      STEPControl_Controller::Init();
      const char* was = Interface_Static::CVal("write.step.schema");
      std::string schema = was == nullptr ? std::string() : std::string(was);
      Interface_Static::SetCVal("write.step.schema", "AP214IS");
      int rc = OK;
      {
        STEPControl_Writer w;
        if (w.Transfer(out, STEPControl_AsIs) != IFSelect_RetDone) {
          set_err(err, errlen, "the STEP writer could not transfer the sewn shape");
          rc = ERR_FAILED;
        } else if (w.Write(path) != IFSelect_RetDone) {
          set_err(err, errlen, "the STEP writer could not write the file");
          rc = ERR_FAILED;
        }
      }
      if (!schema.empty()) Interface_Static::SetCVal("write.step.schema", schema.c_str());
      return rc;
    });
  });
}

/// Number of faces, edges and vertices (TopExp::MapShapes counts).
void occt_model_counts(const OcctModel* m, size_t* nf, size_t* ne, size_t* nv) {
  *nf = (size_t)m->faces.Extent();
  *ne = (size_t)m->edges.Extent();
  *nv = (size_t)m->vertices.Extent();
}

/// Position and tolerance of vertex i (0-based).
int occt_vertex(const OcctModel* m, size_t i, double* xyz, double* tol) {
  if (i >= (size_t)m->vertices.Extent()) return ERR_INDEX;
  return fault_guarded(nullptr, 0, [&]() -> int {
    const TopoDS_Vertex& v = TopoDS::Vertex(m->vertices((int)i + 1));
    gp_Pnt p = BRep_Tool::Pnt(v);
    xyz[0] = p.X();
    xyz[1] = p.Y();
    xyz[2] = p.Z();
    *tol = BRep_Tool::Tolerance(v);
    return OK;
  });
}

/// Edge i (0-based): info, and its 3D curve (location applied) in *curve
/// (null for a degenerate edge or an edge without a 3D curve).
int occt_edge(const OcctModel* m, size_t i, OcctEdgeInfo* info, OcctCurve** curve) {
  *curve = nullptr;
  if (i >= (size_t)m->edges.Extent()) return ERR_INDEX;
  return fault_guarded(nullptr, 0, [&]() -> int {
    TopoDS_Edge e = TopoDS::Edge(m->edges((int)i + 1));
    e.Orientation(TopAbs_FORWARD);
    info->degenerate = BRep_Tool::Degenerated(e) ? 1 : 0;
    info->same_parameter = BRep_Tool::SameParameter(e) ? 1 : 0;
    info->tolerance = BRep_Tool::Tolerance(e);
    TopoDS_Vertex v1, v2;
    TopExp::Vertices(e, v1, v2);
    info->v_start = v1.IsNull() ? -1 : (long)m->vertices.FindIndex(v1) - 1;
    info->v_end = v2.IsNull() ? -1 : (long)m->vertices.FindIndex(v2) - 1;
    double f = 0.0, l = 0.0;
    BRep_Tool::Range(e, f, l);
    info->first = f;
    info->last = l;
    if (!info->degenerate) {
      double cf, cl;
      Handle(Geom_Curve) c = BRep_Tool::Curve(e, cf, cl);
      if (!c.IsNull()) *curve = new OcctCurve{c};
    }
    return OK;
  });
}

/// Face i (0-based): reversed flag, uv bounds (umin, umax, vmin, vmax) and the
/// surface with the face location applied.
int occt_face(const OcctModel* m, size_t i, int* reversed, double* bounds, OcctSurf** surf) {
  *surf = nullptr;
  if (i >= (size_t)m->faces.Extent()) return ERR_INDEX;
  return fault_guarded(nullptr, 0, [&]() -> int {
    const TopoDS_Face& f = TopoDS::Face(m->faces((int)i + 1));
    *reversed = f.Orientation() == TopAbs_REVERSED ? 1 : 0;
    BRepTools::UVBounds(f, bounds[0], bounds[1], bounds[2], bounds[3]);
    Handle(Geom_Surface) s = BRep_Tool::Surface(f);
    if (s.IsNull()) return ERR_NULL;
    *surf = new OcctSurf{s};
    return OK;
  });
}

/// The edge uses of face i's wires, in the face taken FORWARD (so that the
/// material lies to the left of each use in (u, v)): outer wire first, each
/// wire ordered by BRepTools_WireExplorer (explorer order if that misses
/// edges). INTERNAL/EXTERNAL edges are skipped. Call with cap = 0 to get the
/// count in *n; then with a buffer of that size to fill it.
int occt_face_uses(const OcctModel* m, size_t i, OcctUse* buf, size_t cap, size_t* n) {
  *n = 0;
  if (i >= (size_t)m->faces.Extent()) return ERR_INDEX;
  // Pcurves created before a failure are freed here.
  std::vector<OcctCurve2d*> made;
  int rc = fault_guarded(nullptr, 0, [&]() -> int {
    TopoDS_Face f = TopoDS::Face(m->faces((int)i + 1));
    f.Orientation(TopAbs_FORWARD);
    TopoDS_Wire outer = BRepTools::OuterWire(f);
    std::vector<TopoDS_Wire> wires;
    for (TopExp_Explorer w(f, TopAbs_WIRE); w.More(); w.Next()) {
      const TopoDS_Wire& wire = TopoDS::Wire(w.Current());
      if (!outer.IsNull() && wire.IsSame(outer))
        wires.insert(wires.begin(), wire);
      else
        wires.push_back(wire);
    }
    size_t count = 0;
    for (size_t wi = 0; wi < wires.size(); ++wi) {
      std::vector<TopoDS_Edge> edges;
      int n_plain = 0;
      for (TopExp_Explorer x(wires[wi], TopAbs_EDGE); x.More(); x.Next()) ++n_plain;
      for (BRepTools_WireExplorer x(wires[wi], f); x.More(); x.Next()) edges.push_back(x.Current());
      if ((int)edges.size() != n_plain) {
        edges.clear();
        for (TopExp_Explorer x(wires[wi], TopAbs_EDGE); x.More(); x.Next()) edges.push_back(TopoDS::Edge(x.Current()));
      }
      for (const TopoDS_Edge& e : edges) {
        TopAbs_Orientation o = e.Orientation();
        if (o != TopAbs_FORWARD && o != TopAbs_REVERSED) continue;
        if (cap > 0) {
          if (count >= cap) return ERR_SMALL;
          OcctUse& u = buf[count];
          u.wire = (long)wi;
          u.edge = (long)m->edges.FindIndex(e) - 1;
          u.orientation = (int)o;
          u.seam = BRep_Tool::IsClosed(e, f) ? 1 : 0;
          double pf = 0.0, pl = 0.0;
          Handle(Geom2d_Curve) pc = BRep_Tool::CurveOnSurface(e, f, pf, pl);
          u.first = pf;
          u.last = pl;
          u.pcurve = nullptr;
          if (!pc.IsNull()) {
            u.pcurve = new OcctCurve2d{pc};
            made.push_back(u.pcurve);
          }
        }
        ++count;
      }
    }
    *n = count;
    return OK;
  });
  if (rc != OK) {
    for (OcctCurve2d* c : made) delete c;
    *n = 0;
  }
  return rc;
}

// ---------------------------------------------------------------- surfaces

void occt_surf_free(OcctSurf* s) { delete s; }

/// Periods in u and v (0 when not periodic).
int occt_surf_periods(const OcctSurf* s, double* pu, double* pv) {
  return guarded(nullptr, 0, [&]() -> int {
    *pu = s->s->IsUPeriodic() ? s->s->UPeriod() : 0.0;
    *pv = s->s->IsVPeriodic() ? s->s->VPeriod() : 0.0;
    return OK;
  });
}

/// Natural parameter bounds of the surface (may be infinite).
int occt_surf_bounds(const OcctSurf* s, double* b) {
  return guarded(nullptr, 0, [&]() -> int {
    s->s->Bounds(b[0], b[1], b[2], b[3]);
    return OK;
  });
}

/// S(u, v) into out[0..3].
int occt_surf_d0(const OcctSurf* s, double u, double v, double* out) {
  return guarded(nullptr, 0, [&]() -> int {
    gp_Pnt p = s->s->Value(u, v);
    out[0] = p.X(); out[1] = p.Y(); out[2] = p.Z();
    return OK;
  });
}

/// S, Su, Sv into out[0..9].
int occt_surf_d1(const OcctSurf* s, double u, double v, double* out) {
  return guarded(nullptr, 0, [&]() -> int {
    gp_Pnt p;
    gp_Vec du, dv;
    s->s->D1(u, v, p, du, dv);
    const double vals[9] = {p.X(), p.Y(), p.Z(), du.X(), du.Y(), du.Z(), dv.X(), dv.Y(), dv.Z()};
    std::memcpy(out, vals, sizeof(vals));
    return OK;
  });
}

/// S, Su, Sv, Suu, Suv, Svv into out[0..18].
int occt_surf_d2(const OcctSurf* s, double u, double v, double* out) {
  return guarded(nullptr, 0, [&]() -> int {
    gp_Pnt p;
    gp_Vec du, dv, duu, dvv, duv;
    s->s->D2(u, v, p, du, dv, duu, dvv, duv);
    const double vals[18] = {p.X(),   p.Y(),   p.Z(),   du.X(),  du.Y(),  du.Z(),
                             dv.X(),  dv.Y(),  dv.Z(),  duu.X(), duu.Y(), duu.Z(),
                             duv.X(), duv.Y(), duv.Z(), dvv.X(), dvv.Y(), dvv.Z()};
    std::memcpy(out, vals, sizeof(vals));
    return OK;
  });
}

/// Global closest point to p on the surface restricted to [umin,umax]×[vmin,vmax]
/// (GeomAPI_ProjectPointOnSurf): uv in uv[0..2], point in q[0..3].
int occt_surf_project(const OcctSurf* s, const double* p, double umin, double umax, double vmin,
                      double vmax, double* uv, double* q) {
  return guarded(nullptr, 0, [&]() -> int {
    GeomAPI_ProjectPointOnSurf proj(gp_Pnt(p[0], p[1], p[2]), s->s, umin, umax, vmin, vmax);
    if (!proj.IsDone() || proj.NbPoints() == 0) return ERR_FAILED;
    proj.LowerDistanceParameters(uv[0], uv[1]);
    gp_Pnt r = proj.NearestPoint();
    q[0] = r.X(); q[1] = r.Y(); q[2] = r.Z();
    return OK;
  });
}

// ---------------------------------------------------------------- 3D curves

void occt_curve_free(OcctCurve* c) { delete c; }

/// C(t) into out[0..3] and C'(t) into out[3..6].
int occt_curve_d1(const OcctCurve* c, double t, double* out) {
  return guarded(nullptr, 0, [&]() -> int {
    gp_Pnt p;
    gp_Vec d;
    c->c->D1(t, p, d);
    out[0] = p.X(); out[1] = p.Y(); out[2] = p.Z();
    out[3] = d.X(); out[4] = d.Y(); out[5] = d.Z();
    return OK;
  });
}

/// C(t), C'(t), C''(t) into out[0..9].
int occt_curve_d2(const OcctCurve* c, double t, double* out) {
  return guarded(nullptr, 0, [&]() -> int {
    gp_Pnt p;
    gp_Vec d1, d2;
    c->c->D2(t, p, d1, d2);
    const double vals[9] = {p.X(), p.Y(), p.Z(), d1.X(), d1.Y(), d1.Z(), d2.X(), d2.Y(), d2.Z()};
    std::memcpy(out, vals, sizeof(vals));
    return OK;
  });
}

/// Global closest point to p on the curve within [t0, t1]
/// (GeomAPI_ProjectPointOnCurve): parameter in *t, point in q[0..3].
int occt_curve_project(const OcctCurve* c, const double* p, double t0, double t1, double* t, double* q) {
  return guarded(nullptr, 0, [&]() -> int {
    GeomAPI_ProjectPointOnCurve proj(gp_Pnt(p[0], p[1], p[2]), c->c, t0, t1);
    if (proj.NbPoints() == 0) return ERR_FAILED;
    *t = proj.LowerDistanceParameter();
    gp_Pnt r = proj.NearestPoint();
    q[0] = r.X(); q[1] = r.Y(); q[2] = r.Z();
    return OK;
  });
}

// ---------------------------------------------------------------- pcurves

void occt_curve2d_free(OcctCurve2d* c) { delete c; }

/// c(t) into out[0..2] and c'(t) into out[2..4].
int occt_curve2d_d1(const OcctCurve2d* c, double t, double* out) {
  return guarded(nullptr, 0, [&]() -> int {
    gp_Pnt2d p;
    gp_Vec2d d;
    c->c->D1(t, p, d);
    out[0] = p.X(); out[1] = p.Y();
    out[2] = d.X(); out[3] = d.Y();
    return OK;
  });
}

}  // extern "C"
